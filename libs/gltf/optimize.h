// GPU-friendly ordering of a primitive's data with meshoptimizer (issue 14: vertex cache,
// overdraw and vertex fetch optimisation of every mesh). The drawn result is the same: the same
// triangles (each keeping its winding) and lines over the same vertices, reordered.
//   TRIANGLES: meshopt_optimizeVertexCache, then meshopt_optimizeOverdraw (threshold 1.05: up to
//              5 % worse vertex cache for less overdraw), then meshopt_optimizeVertexFetchRemap
//              (vertices in first-use order; unreferenced vertices dropped).
//   LINES:     vertex fetch only (the cache and overdraw optimisers are for triangles).
//   POINTS and non-indexed primitives: unchanged.
// Deterministic (meshoptimizer is single-threaded and has no randomness).
#pragma once

#include "libs/gltf/scene.h"

namespace sylva::gltf {

void optimize_primitive(Primitive& p);
void optimize_scene(Scene& s);  // every primitive of every mesh

}  // namespace sylva::gltf
