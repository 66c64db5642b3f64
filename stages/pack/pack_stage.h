// Stage `pack`: lod chains -> an asset pack (per species <species>.glb with MSFT_lod,
// <species>_lod<i>.glb, <species>.lod.json; manifest.json). Parameters in docs/stages/pack.md.
#pragma once

#include <memory>

#include "pipeline/stage.h"

namespace sylva {
std::unique_ptr<Stage> make_pack_stage();
}
