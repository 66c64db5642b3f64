// Stage `pack`: lod chains -> an asset pack (per species <species>.glb with MSFT_lod,
// <species>_lod<i>.glb, <species>.lod.json; manifest.json). Parameters in docs/stages/pack.md.
// Lives in the graphics module: the measured level choice renders.
#pragma once

#include <functional>
#include <memory>

#include "libs/render/renderer.h"
#include "pipeline/stage.h"

namespace sylva {
// `renderer` gives the renderer of the measured level choice (`measure: true`), asked for only
// when a node measures; empty: the process's headless renderer (libs/render/shared_renderer.h).
std::unique_ptr<Stage> make_pack_stage(std::function<render::Renderer&()> renderer = {});
}  // namespace sylva
