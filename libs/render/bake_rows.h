// Private: the atlas layout of an impostor bake (impostor_renderer.cpp): the views are drawn one
// atlas row at a time, every view of a row (the views that share its y and height) in one
// instanced draw per primitive, each view's frame taken from a uniform array by gl_InstanceID.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "libs/render/gl_util.h"
#include "libs/render/impostor_renderer.h"

namespace sylva::render::detail {

// One atlas row: the views that share its y and height, and their uniforms.
struct BakeRow {
  int y = 0, h = 0;                // atlas pixels, top-left origin
  std::vector<std::size_t> views;  // indices into the bake's views, in view order
  std::vector<float> uniforms;     // 5 vec4 per view: shaders/bake.vert's u_views
};

// Throws RenderError for an atlas beyond `limits`, an msaa the device lacks, a line width below 1
// texel or a line alpha scale outside (0, 1], and a view outside the atlas or of no extent.
void validate_bake(std::span<const BakeView> views, const BakeOptions& o, const DeviceLimits& limits);

// The rows of `views`, by (y, h) ascending. Throws RenderError for a row of more than
// kMaxRowViews views (bake_programs.h).
std::vector<BakeRow> plan_rows(std::span<const BakeView> views, const BakeOptions& o);

}  // namespace sylva::render::detail
