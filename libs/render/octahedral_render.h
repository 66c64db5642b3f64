// Private: ImpostorRenderer::render_octahedral (impostor_renderer.h), an impostor's instances
// alone in a view: the reference shader (shaders/octahedral_impostor.*) on one camera-facing
// quad per instance, the maps premultiplied by coverage before upload (the shader's contract),
// the instances far to near, blended over the background with alpha = coverage. Every function
// expects the context current.
#pragma once

#include <span>
#include <vector>

#include "libs/image/image.h"
#include "libs/render/camera.h"
#include "libs/render/gl_util.h"
#include "libs/render/impostor_renderer.h"

namespace sylva::render::detail {

// One image per camera (width x height, top row first) of `imp` drawn with `program` (the
// reference shader, linked). Throws RenderError for options beyond `limits`, or maps or geometry
// that do not fit together.
std::vector<image::Image> render_octahedral_views(GLuint program, const DeviceLimits& limits,
                                                  const OctahedralImpostor& imp,
                                                  std::span<const Camera> cameras, const RenderOptions& o,
                                                  const ImpostorDrawOptions& draw);

}  // namespace sylva::render::detail
