// The impostor level (see impostor_level.h). The GLB container (glTF 2.0 spec §4.4): a 12-byte
// header (magic "glTF", version 2, total length), then chunks of (length, type, data), the first
// one JSON, the optional second one BIN; lengths are little-endian u32 and chunks 4-byte aligned.
#include "stages/forest/impostor_level.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace sylva::forest {

namespace {

std::uint32_t u32_at(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int b = 0; b < 4; ++b)
    v |= std::uint32_t(static_cast<unsigned char>(s[at + std::size_t(b)])) << (8 * b);
  return v;
}

constexpr std::uint32_t kMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kJson = 0x4E4F534A;   // "JSON"
constexpr std::uint32_t kBin = 0x004E4942;    // "BIN\0"

}  // namespace

ImpostorLevel impostor_level_source(const std::string& glb, const std::string& name,
                                    const std::string& what) {
  auto fail = [&](const std::string& m) -> void { throw std::invalid_argument(what + ": " + m); };
  if (glb.size() < 20 || u32_at(glb, 0) != kMagic) fail("not a GLB file (no glTF header)");
  if (u32_at(glb, 4) != 2) fail("GLB version " + std::to_string(u32_at(glb, 4)) + " (expected 2)");
  if (u32_at(glb, 8) != glb.size()) fail("the GLB header's length does not match the file's size");
  const std::size_t json_len = u32_at(glb, 12);
  if (u32_at(glb, 16) != kJson || 20 + json_len > glb.size()) fail("the first GLB chunk is not a JSON chunk");
  ImpostorLevel out;
  try {
    out.source.gltf = nlohmann::json::parse(glb.substr(20, json_len));
  } catch (const nlohmann::json::exception& e) {
    fail(std::string("the GLB's JSON chunk does not parse: ") + e.what());
  }
  const nlohmann::json& g = out.source.gltf;
  if (!g.contains("buffers") || !g["buffers"].is_array() || g["buffers"].size() != 1 ||
      g["buffers"][0].contains("uri"))
    fail("expected exactly one buffer, the GLB's BIN chunk");
  if (!g.contains("meshes") || !g["meshes"].is_array() || g["meshes"].size() != 1)
    fail("expected exactly one mesh");
  const std::size_t bin_at = 20 + ((json_len + 3) & ~std::size_t(3));
  if (bin_at + 8 > glb.size() || u32_at(glb, bin_at + 4) != kBin) fail("no BIN chunk after the JSON chunk");
  const std::size_t bin_len = u32_at(glb, bin_at);
  const auto bytes = g["buffers"][0].value("byteLength", std::size_t(0));
  if (bin_at + 8 + bin_len > glb.size() || bytes > bin_len)
    fail("the BIN chunk is shorter than the buffer's byteLength");
  out.bin = glb.substr(bin_at + 8, bytes);
  out.source.bin_name = name + "_impostor.bin";
  out.source.bin_bytes = bytes;
  out.source.image_prefix = name + "_";
  return out;
}

double impostor_switch_distance_m(double recorded_m, const lodmodel::Camera& impostor_camera,
                                  double impostor_pixel_error_px, const lodmodel::Camera& chain_camera,
                                  double chain_pixel_error_px) {
  const double k =
      lodmodel::distance_scale(impostor_camera, impostor_pixel_error_px, chain_camera, chain_pixel_error_px);
  // The recorded distance itself where the cameras agree up to rounding (a chain's camera comes
  // back from lod.json's degrees): no drift of a proven distance by an ulp.
  return std::abs(k - 1) <= 1e-9 ? recorded_m : recorded_m * k;
}

}  // namespace sylva::forest
