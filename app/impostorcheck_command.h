// `sylva impostorcheck [RECIPE] [--node NODE]... [options]`: the visual proof of the impostors
// (docs/stages/impostor.md, "impostorcheck").
//
//  1. Loads the recipe and picks its `impostor` nodes (all, or those named by --node); builds them.
//  2. Per node, the full-detail model of what the impostor was baked from: for an input of stage
//     lod the chain's epsilon = 0 model, its full.glb (what `sylva lodcheck` judges against;
//     app/full_detail.h), for a mesh the mesh.
//  3. Renders the impostor (octahedral kinds with the reference shader, billboards as impostor.glb)
//     and the full detail from the same cameras at the impostor's switch distance, from 12
//     azimuths x 3 elevations that are not frame directions (stages/impostor/check), and judges
//     coverage and colour per view.
//  4. Prints a table per node and writes impostorcheck.json plus, per view, both renders and a
//     heat-map to <out>/<recipe>/impostorcheck/<node>/.
//
// Exit codes: 0 every view of every node passed; 1 a view failed, the build failed, or no
// headless OpenGL; 2 usage or recipe error; 130 interrupted.
#pragma once

#include <memory>

#include "app/cli.h"

namespace sylva {
std::unique_ptr<CliCommand> make_impostorcheck_command();
}
