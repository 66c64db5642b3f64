// What stage `verify` declares (name, version, parameters, inputs, output type), apart from its
// implementation: the `sylva` binary registers the stage from this alone, and loads the
// renderer only when a verify node runs (docs/architecture.md, "Heavy libraries load lazily").
#pragma once

#include "pipeline/stage.h"

namespace sylva {
StageInfo verify_stage_info();
}
