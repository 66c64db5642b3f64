// The process-wide headless scene renderer, for stages and commands that draw during a build
// (verify, impostorcheck). Created on first use and never destroyed: tearing an EGL display down
// from a static destructor races Mesa's own exit handlers, and every EGL context of the process
// shares one display, so destroying one renderer would terminate the display under the others.
// A failure to create it is not remembered, so each caller reports it (the same one-line
// RenderUnavailableError). The impostor renderer has its own: shared_impostor_renderer().
#pragma once

#include "libs/render/renderer.h"

namespace sylva::render {

Renderer& shared_renderer();

}  // namespace sylva::render
