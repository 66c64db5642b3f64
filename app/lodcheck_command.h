// `sylva lodcheck [RECIPE] [--node NODE]... [options]`: the visual proof of the LOD chains
// (docs/stages/lod.md, "lodcheck").
//
//  1. Loads the recipe and picks its `lod` nodes (all, or those named by --node), then its
//     `forest` nodes (all, or those named); builds them (app/check_command.h).
//  2. Per lod node, reads the full-detail model the stage wrote, full.glb (epsilon = 0;
//     app/full_detail.h) and, for every level, renders the level's file as written (lod<i>.gltf)
//     and the full-detail model from the same camera at the level's switch distance
//     (lod/check/lodcheck.h). A forest node is checked against its species' full.glb
//     (stages/forest/check/forestcheck.h).
//  3. Prints a table per node (level, epsilon, distance, view, primitives, footprint, failing
//     fraction, mean and max error, verdict) and writes lodcheck.json plus, per view, the two
//     renders and a diff heat-map to <out>/<recipe>/lodcheck/<node>/.
//
// --candidates DIR adds another simplifier's models (DIR/lod<i>.glb, one per level) rendered and
// measured the same way (tools/compare_gltfpack.sh); they are reported, never judged.
// --write-full FILE writes the full-detail model as a GLB (one node only): full.glb as the stage
// wrote it, or with --branches-only without its leaves and needles.
// --branches-only draws the bark and branch lines only (no leaves, no needles).
//
// Exit codes: 0 every level of every node passed; 1 a level failed, the build failed, or no
// headless OpenGL; 2 usage or recipe error; 130 interrupted.
#pragma once

#include <memory>

#include "app/cli.h"

namespace sylva {
std::unique_ptr<CliCommand> make_lodcheck_command();
}
