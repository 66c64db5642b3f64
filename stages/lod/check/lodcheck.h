// The visual proof of a LOD chain (`sylva lodcheck`): draw each level at its switch distance and
// the full-detail tree from the same camera, and measure how much the images differ. The
// machinery (cameras, cropping, supersampling, the verdict) is libs/check/view_check.h, shared
// with the pack stage's measured level choice; this header names it for the lod stage's chains
// and adds what only the lod stage's files have (the bark materials, for --branches-only).
#pragma once

#include "libs/check/view_check.h"
#include "libs/render/scene.h"
#include "stages/lod/chain.h"

namespace sylva::lod {

using LodCheckOptions = check::ViewCheckOptions;
using CheckSubject = check::CheckSubject;
using ViewCheck = check::ViewCheck;
using CheckImageSink = check::CheckImageSink;
using check::check_camera;

// check::check_subjects, with the chain's camera (ChainOptions::camera, a lodmodel::Camera).
using check::check_subjects;

// Keeps only the branch primitives of a scene (materials "bark" and "bark_lines" as lod_gltf.h
// names them): for comparing branch simplification without the foliage.
render::Scene branches_only(const render::Scene& scene);

}  // namespace sylva::lod
