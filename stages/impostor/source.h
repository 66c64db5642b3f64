// Which geometry an impostor is baked from. A `mesh` artifact is baked as it is; from a `lod`
// artifact the stage bakes the coarsest level whose spatial error epsilon is at most one atlas
// texel: that level is within a texel of the full detail everywhere, so the atlas cannot tell it
// from finer levels, and it is the cheapest to draw 256 times (docs/stages/impostor.md, "Source").
// The levels are lod.json's (file, epsilon_m, pixel_error_px, switch_distance_m of each level),
// read with libs/lodchain, the format's one reader (docs/stages/lod.md "Outputs").
#pragma once

#include <string>
#include <vector>

#include "libs/lodchain/lod_chain.h"
#include "libs/render/scene.h"
#include "stages/impostor/layout.h"

namespace sylva::impostor {

// What an impostor is baked from (impostor.json's "source"; bake.h uses epsilon and
// line_pixel_m).
struct SourceDesc {
  std::string type = "mesh";  // "mesh" or "lod"
  std::string file;           // the file baked
  int level = -1;             // LOD level, -1 for a mesh
  double epsilon = 0;         // the level's epsilon (m), 0 for a mesh
  double line_pixel_m = 0;    // pixel size the source's line alphas are for (m), 0: no line alphas
};

struct LodLevelRef {
  std::string file;            // e.g. "lod3.glb"
  double epsilon = 0;          // m
  double pixel_error = 0;      // delta the level was built for (px)
  double switch_distance = 0;  // m
};

// The levels of a chain (lodchain::read_lod_chain) the stage may bake, finest first: every level,
// or only level 0 when it is an imported tree's own model (source.model_triangles > 0: the user's
// model is the truth the impostor must show, docs/stages/impostor.md "Source").
std::vector<LodLevelRef> lod_level_refs(const lodchain::LodChain& chain);

// Index of the coarsest level with epsilon <= texel_m; the finest (0) when none qualifies.
std::size_t choose_level(const std::vector<LodLevelRef>& levels, double texel_m);

// The level of a lod chain the stage bakes, for these layout parameters: the texel is estimated
// from `coarsest` (the scene of levels.back(), which measures the tree: every level lies within
// its epsilon of the others) widened by the coarsest level's epsilon, so that the estimate never
// falls short of a finer level's extent; then choose_level(). type "lod", the level's file,
// index, epsilon and line pixel (epsilon / pixel_error; 0 for a level without a pixel error).
// Throws std::invalid_argument for an empty list or parameters that give no atlas.
SourceDesc choose_source(const std::vector<LodLevelRef>& levels, const render::Scene& coarsest,
                         const LayoutParams& layout);

}  // namespace sylva::impostor
