// The error model's choice: the lod stage proved each level from its own switch distance, so
// without a measurement a level is kept where it was proven, unless it saves too little or the
// impostor is proven before it.
#include <cstdio>
#include <string>

#include "stages/pack/level_choice.h"

namespace sylva::pack {

std::vector<LevelChoice> model_choice(const Prepared& p, const PackOptions& options) {
  std::vector<LevelChoice> out;
  const double keep_at_most = 1 - options.min_saving;
  const LevelChoice* previous = nullptr;  // the level kept last
  auto too_little = [&](const LevelChoice& c) {
    return previous && double(c.primitives) > keep_at_most * double(previous->primitives);
  };
  auto saving_reason = [&](const LevelChoice& c) {
    const double saved =
        previous->primitives == 0 ? 0 : 1 - double(c.primitives) / double(previous->primitives);
    char buf[160];
    std::snprintf(
        buf, sizeof buf,
        "saves %.3g of the primitives of the level before it (%llu -> %llu), less than min_saving %.3g",
        saved, static_cast<unsigned long long>(previous->primitives),
        static_cast<unsigned long long>(c.primitives), options.min_saving);
    return std::string(buf);
  };
  const Candidate* impostor = p.candidates.back().impostor ? &p.candidates.back() : nullptr;
  out.reserve(p.candidates.size());
  for (const Candidate& k : p.candidates) {
    LevelChoice c;
    c.impostor = k.impostor;
    c.source_level = k.source_level;
    c.switch_distance_m = k.switch_distance_m;
    c.primitives = k.primitives;
    if (!k.impostor && k.source_level == 0) {
      c.kept = true;
    } else if (!k.impostor && impostor && c.switch_distance_m >= impostor->switch_distance_m) {
      // (impostor->switch_distance_m is at least level 0's, so this compares with impostor.json's.)
      c.reason = "the impostor is proven from " + describe(impostor->switch_distance_m) +
                 " m, before this level's switch distance " + describe(c.switch_distance_m) + " m";
    } else if (too_little(c)) {
      c.reason = saving_reason(c);
    } else {
      c.kept = true;
    }
    out.push_back(c);
    if (out.back().kept) previous = &out.back();
  }
  return out;
}

}  // namespace sylva::pack
