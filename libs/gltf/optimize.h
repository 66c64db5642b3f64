// GPU-friendly ordering of a primitive's data with meshoptimizer (issue 14: vertex cache,
// overdraw and vertex fetch optimisation of every mesh). The drawn result is the same: the same
// triangles (each keeping its winding) and lines over the same vertices, reordered.
//   TRIANGLES, OptimizeOrder::kGpu: meshopt_optimizeVertexCache, then meshopt_optimizeOverdraw
//              (threshold 1.05: up to 5 % worse vertex cache for less overdraw), then
//              meshopt_optimizeVertexFetchRemap (vertices in first-use order; unreferenced
//              vertices dropped).
//   TRIANGLES, OptimizeOrder::kSize: meshopt_optimizeVertexCacheStrip (a cache order that also
//              follows strips: consecutive triangles share edges, which meshoptimizer's index
//              and vertex codecs compress better; gltfpack -cc's order), no overdraw pass, then
//              the same fetch remap.
//   LINES, OptimizeOrder::kGpu: vertex fetch only (the cache and overdraw optimisers are for
//              triangles).
//   LINES, OptimizeOrder::kSize: unchanged. The lod stage writes a branch's segments and their
//              vertices in order along it, with a joint's vertex repeated once per segment it
//              ends (own normal and colour); first-use order interleaves those copies with the
//              next joint's and meshoptimizer's vertex codec, which codes each vertex against
//              the one before it, compresses the lines' positions ~25 % worse (the Scots pine's
//              lod4: 88,947 against 65,928 bytes; gltfpack -cc keeps the order too).
//   POINTS and non-indexed primitives: unchanged.
// Deterministic (meshoptimizer is single-threaded and has no randomness).
#pragma once

#include "libs/gltf/scene.h"

namespace sylva::gltf {

enum class OptimizeOrder { kGpu, kSize };

void optimize_primitive(Primitive& p, OptimizeOrder order = OptimizeOrder::kGpu);
void optimize_scene(Scene& s, OptimizeOrder order = OptimizeOrder::kGpu);  // every primitive of every mesh

}  // namespace sylva::gltf
