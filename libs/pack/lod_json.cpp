#include "libs/pack/lod_json.h"

#include <nlohmann/json.hpp>

namespace sylva::pack {

std::string write_lod_json(const LodDescription& d) {
  nlohmann::json levels = nlohmann::json::array();
  for (const LodLevel& l : d.levels)
    levels.push_back({{"file", l.file},
                      {"epsilon_m", l.epsilon_m},
                      {"pixel_error_px", l.pixel_error_px},
                      {"switch_distance_m", l.switch_distance_m},
                      {"screen_coverage", l.screen_coverage},
                      {"triangles", l.triangles},
                      {"lines", l.lines},
                      {"bytes", l.bytes},
                      {"position_bits", l.position_bits},
                      {"position_error_m", l.position_error_m},
                      {"position_float", l.position_float}});
  const nlohmann::json j = {{"format", "sylva-pack-lod"},
                            {"version", 2},
                            {"species", d.species},
                            {"chain", d.chain},
                            {"levels", std::move(levels)}};
  return j.dump(2) + "\n";
}

}  // namespace sylva::pack
