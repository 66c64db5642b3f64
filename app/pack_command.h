// `sylva pack diff OLD_MANIFEST NEW_MANIFEST [--json]`: the files two asset packs differ in
// (libs/pack/manifest.h), by SHA-256: added, changed, removed. Exit 0, or 1 when a manifest
// cannot be read (the message names the file and element).
#pragma once
#include "app/cli.h"

namespace sylva {
std::unique_ptr<CliCommand> make_pack_command();
}
