// What stage `forest` declares (name, version, parameters, inputs), without its implementation:
// linked into the `sylva` binary, which loads the implementation from the graphics module when a
// forest node runs (it reads height and density maps with OpenImageIO). docs/stages/forest.md.
#pragma once

#include "pipeline/stage.h"

namespace sylva {

StageInfo forest_stage_info();

}  // namespace sylva
