// `sylva inspect FILE [--json]`: statistics of a tree file (.sylt).
#pragma once
#include "app/cli.h"

namespace sylva {
std::unique_ptr<CliCommand> make_inspect_command();
}
