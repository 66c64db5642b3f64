// Why a pass over the JSON rather than at each value: tinygltf serialises the model, and every
// number it holds is a double; the pass sees the document as written, whatever fills it.
#include "libs/gltf/json_numbers.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace sylva::gltf {

double float_json(double v) {
  if (!std::isfinite(v)) return v;
  char buf[64];
  const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf - 1, static_cast<float>(v));
  *r.ptr = '\0';
  return std::strtod(buf, nullptr);
}

namespace {

void compact(nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::number_float: {
      const double d = j.get<double>();
      if (!std::isfinite(d)) return;
      if (std::trunc(d) == d && std::fabs(d) < 9007199254740992.0) {
        j = static_cast<std::int64_t>(d);
        return;
      }
      j = float_json(d);
      return;
    }
    case nlohmann::json::value_t::array:
      for (nlohmann::json& v : j) compact(v);
      return;
    case nlohmann::json::value_t::object:
      for (auto it = j.begin(); it != j.end(); ++it)
        if (it.key() != "extras") compact(it.value());
      return;
    default:
      return;
  }
}

}  // namespace

void compact_gltf_numbers(nlohmann::json& gltf) {
  compact(gltf);
  if (!gltf.contains("meshes")) return;
  for (nlohmann::json& mesh : gltf["meshes"]) {
    if (!mesh.contains("primitives")) continue;
    for (nlohmann::json& p : mesh["primitives"]) {
      const auto it = p.find("mode");
      if (it != p.end() && it->is_number_integer() && it->get<int>() == 4) p.erase(it);
    }
  }
}

}  // namespace sylva::gltf
