// The level choice of source.h.
#include "stages/impostor/source.h"

#include <cmath>
#include <stdexcept>

#include "libs/lodmodel/lod_model.h"

namespace sylva::impostor {

std::vector<LodLevelRef> lod_level_refs(const lodchain::LodChain& chain) {
  std::vector<LodLevelRef> out;
  for (const lodchain::Level& l : chain.levels) {
    out.push_back({l.file, l.epsilon_m, l.pixel_error_px, l.switch_distance_m});
    // An imported tree is baked from its own model, never from its reconstruction.
    if (chain.source.model_triangles > 0) break;
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
  d.line_pixel_m =
      levels[i].pixel_error > 0 ? lodmodel::switch_pixel_size(levels[i].epsilon, levels[i].pixel_error) : 0;
  return d;
}

}  // namespace sylva::impostor
