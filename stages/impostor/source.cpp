// The level choice of source.h.
#include "stages/impostor/source.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace sylva::impostor {

std::vector<LodLevelRef> parse_lod_levels(const std::string& text, const std::string& source) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::invalid_argument(source + ": invalid JSON: " + e.what());
  }
  if (!j.is_object() || !j.contains("levels") || !j["levels"].is_array() || j["levels"].empty())
    throw std::invalid_argument(source + ": not a lod summary (no 'levels' list)");
  std::vector<LodLevelRef> out;
  for (std::size_t i = 0; i < j["levels"].size(); ++i) {
    const nlohmann::json& l = j["levels"][i];
    const std::string where = source + ": levels[" + std::to_string(i) + "]";
    if (!l.is_object() || !l.contains("file") || !l["file"].is_string())
      throw std::invalid_argument(where + " has no 'file'");
    if (!l.contains("epsilon_m") || !l["epsilon_m"].is_number() || !(l["epsilon_m"].get<double>() >= 0))
      throw std::invalid_argument(where + " has no valid 'epsilon_m'");
    LodLevelRef r;
    r.file = l["file"].get<std::string>();
    r.epsilon = l["epsilon_m"].get<double>();
    r.pixel_error =
        l.contains("pixel_error_px") && l["pixel_error_px"].is_number()   ? l["pixel_error_px"].get<double>()
        : j.contains("pixel_error_px") && j["pixel_error_px"].is_number() ? j["pixel_error_px"].get<double>()
                                                                          : 0.0;
    if (l.contains("switch_distance_m") && l["switch_distance_m"].is_number())
      r.switch_distance = l["switch_distance_m"].get<double>();
    out.push_back(std::move(r));
  }
  return out;
}

std::size_t choose_level(const std::vector<LodLevelRef>& levels, double texel_m) {
  std::size_t best = 0;
  for (std::size_t i = 0; i < levels.size(); ++i)
    if (levels[i].epsilon <= texel_m) best = i;
  return best;
}

SourceDesc choose_source(const std::vector<LodLevelRef>& levels, const render::Scene& coarsest,
                         const LayoutParams& layout) {
  if (levels.empty()) throw std::invalid_argument("choose_source: no levels");
  SourceGeometry g = measure(coarsest);
  g.radius += levels.back().epsilon;
  g.horizontal_radius += levels.back().epsilon;
  const std::size_t i = choose_level(levels, atlas_texel(layout, g));
  SourceDesc d;
  d.type = "lod";
  d.file = levels[i].file;
  d.level = int(i);
  d.epsilon = levels[i].epsilon;
  d.line_pixel_m = levels[i].pixel_error > 0 ? levels[i].epsilon / levels[i].pixel_error : 0;
  return d;
}

}  // namespace sylva::impostor
