// What stage `impostor` declares (name, version, parameters, inputs, output type), apart from its
// implementation: the `sylva` binary registers the stage from this alone, and loads the renderer
// (libsylva_gfx.so) only when an impostor node runs (docs/architecture.md, "Heavy libraries load
// lazily"). Parameters: docs/stages/impostor.md.
#pragma once

#include "pipeline/stage.h"

namespace sylva {
StageInfo impostor_stage_info();
}
