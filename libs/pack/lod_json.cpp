#include "libs/pack/lod_json.h"

#include <nlohmann/json.hpp>

#include "libs/pack/level_json.h"

namespace sylva::pack {

nlohmann::json level_json(const LodLevel& l) {
  nlohmann::json level = {{"file", l.file},
                          {"kind", l.kind},
                          {"source_level", l.source_level},
                          {"primitives", l.primitives},
                          {"epsilon_m", l.epsilon_m},
                          {"pixel_error_px", l.pixel_error_px},
                          {"switch_distance_m", l.switch_distance_m},
                          {"screen_coverage", l.screen_coverage},
                          {"triangles", l.triangles},
                          {"lines", l.lines},
                          {"bytes", l.bytes},
                          {"position_bits", l.position_bits},
                          {"position_error_m", l.position_error_m},
                          {"position_float", l.position_float}};
  if (!l.impostor_kind.empty()) level["impostor_kind"] = l.impostor_kind;
  if (l.measured)
    level["measured"] = {{"failing_fraction", l.measured->failing_fraction},
                         {"coverage_mean_error", l.measured->coverage_mean_error},
                         {"passed", l.measured->passed}};
  return level;
}

std::string write_lod_json(const LodDescription& d) {
  nlohmann::json levels = nlohmann::json::array();
  for (const LodLevel& l : d.levels) levels.push_back(level_json(l));
  nlohmann::json dropped = nlohmann::json::array();
  for (const DroppedLevel& l : d.dropped)
    dropped.push_back({{"kind", l.kind},
                       {"source_level", l.source_level},
                       {"switch_distance_m", l.switch_distance_m},
                       {"primitives", l.primitives},
                       {"reason", l.reason}});
  const nlohmann::json j = {{"format", "sylva-pack-lod"},  {"version", 4},
                            {"species", d.species},        {"chain", d.chain},
                            {"levels", std::move(levels)}, {"dropped", std::move(dropped)}};
  return j.dump(2) + "\n";
}

}  // namespace sylva::pack
