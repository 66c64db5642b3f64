// Stage `import`: one file -> tree (tree.sylt). Parameters and rules: docs/stages/import.md.
#pragma once

#include <memory>

#include "pipeline/stage.h"

namespace sylva {

std::unique_ptr<Stage> make_import_stage();

}  // namespace sylva
