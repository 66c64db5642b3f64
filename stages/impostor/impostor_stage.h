// Stage `impostor`: mesh or lod -> impostor (impostor.json, impostor_color.png,
// impostor_normal.png, impostor.glb). Parameters and formats: docs/stages/impostor.md.
#pragma once

#include <functional>
#include <memory>

#include "libs/render/impostor_renderer.h"
#include "pipeline/stage.h"
#include "stages/impostor/bake.h"

namespace sylva {

// The stage with the process-wide headless renderer (render::shared_impostor_renderer()).
std::unique_ptr<Stage> make_impostor_stage();
// The same with another renderer (tests).
std::unique_ptr<Stage> make_impostor_stage(std::function<render::ImpostorRenderer&()> renderer);

// The bake parameters of an impostor node's complete (defaults filled) parameters, as the stage
// reads them (for `sylva impostorcheck`). Throws std::invalid_argument if one is missing.
impostor::BakeParams bake_params_from(const Value::Object& params);

}  // namespace sylva
