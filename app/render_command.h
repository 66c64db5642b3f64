// `sylva render FILE [--camera SET] [--view NAME]... -o OUT`: draws a .glb/.gltf file from the
// views of a camera set into PNG files, for people looking at assets (docs/renderer.md).
//
//   -o out.png   one image: the view named by --view, else the set's first view
//   -o DIR       one DIR/<view>.png per view (every view, or those named by --view)
//
// Exit codes: 0 written; 1 the asset cannot be loaded (one line naming the file), no headless
// OpenGL, rendering or writing failed; 2 usage: bad options, unknown view, invalid camera set.
#pragma once

#include <memory>

#include "app/cli.h"

namespace sylva {
std::unique_ptr<CliCommand> make_render_command();
}
