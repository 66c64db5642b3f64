// `sylva lodcheck [RECIPE] [--node NODE]... [options]`: the visual proof of the LOD chains
// (docs/stages/lod.md, "lodcheck").
//
//  1. Loads the recipe and picks its `lod` nodes (all, or those named by --node); builds them.
//  2. Per node, rebuilds the full-detail model of its tree in memory (epsilon = 0, lod/chain.h)
//     and, for every level, renders the level's GLB as written (lod<i>.glb) and the full-detail
//     model from the same camera at the level's switch distance (lod/check/lodcheck.h).
//  3. Prints a table per node (level, epsilon, distance, view, primitives, footprint, failing
//     fraction, mean and max error, verdict) and writes lodcheck.json plus, per view, the two
//     renders and a diff heat-map to <out>/<recipe>/lodcheck/<node>/.
//
// --candidates DIR adds another simplifier's models (DIR/lod<i>.glb, one per level) rendered and
// measured the same way (tools/compare_gltfpack.sh); they are reported, never judged.
// --write-full FILE writes the full-detail model as a GLB (one node only).
// --branches-only draws the bark and branch lines only (no leaves, no needles).
//
// Exit codes: 0 every level of every node passed; 1 a level failed, the build failed, or no
// headless OpenGL; 2 usage or recipe error; 130 interrupted.
#pragma once

#include <memory>

#include "app/cli.h"

namespace sylva {
std::unique_ptr<CliCommand> make_lodcheck_command(const StageRegistry& registry);
}
