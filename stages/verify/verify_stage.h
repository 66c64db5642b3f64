// Stage `verify`: renders every view of a camera set for every glTF file of its inputs and
// compares them with reference images; writes the renderings, heat maps, report.json, junit.xml
// and report.html, and fails (StageError, so the build exits 1) when any view does not pass.
// Parameters, outputs and the update workflow: docs/stages/verify.md.
//
// The helpers below are shared with the `sylva verify` command, which runs the same core outside
// the cache so that reports exist even when verification fails.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "libs/render/renderer.h"
#include "pipeline/stage.h"
#include "pipeline/value.h"
#include "stages/verify/verify_core.h"

namespace sylva {

// The stage with the process-wide headless renderer (created on first use, shared by every
// verify node of the process; the renderer serialises calls itself).
std::unique_ptr<Stage> make_verify_stage();
// The stage with a renderer of the caller's choice (tests pass a fake). `renderer` is called once
// per run and must return a renderer that outlives the run; it may throw
// render::RenderUnavailableError.
std::unique_ptr<Stage> make_verify_stage(std::function<render::Renderer&()> renderer);

namespace verify {

// The glTF files to verify, in input order: every file ending in .glb or .gltf of every input
// artifact, in name order. An artifact with one such file gives the asset its node's name
// (`mesh_oak`); with several, each is `<node>.<file stem>` (`lod_oak.lod0`). Throws StageError
// naming the input when an artifact has none.
std::vector<Asset> assets_from_inputs(const std::vector<InputArtifact>& inputs);

// The thresholds a verify node's parameters ask for (params complete, as StageContext::params()).
Thresholds thresholds_from_params(const Value::Object& params);

// The process-wide headless renderer (what make_verify_stage() uses). Throws
// render::RenderUnavailableError, every time it is asked, when there is no EGL/OpenGL.
render::Renderer& shared_renderer();

}  // namespace verify
}  // namespace sylva
