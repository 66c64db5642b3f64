// Private: drawing Scene::impostors inside the scene renderer (gl_renderer.cpp), into the same
// target and depth buffer as the meshes, with the reference shader (shaders/octahedral_impostor.*,
// the one `sylva impostorcheck` proves; impostor_renderer.h draws impostors alone with it).
//
// Per view: every instance of every set sorted far to near by the view depth of its sphere centre
// (ties: set, then instance order), drawn in runs of consecutive instances of one set, each run
// one instanced draw of a camera-facing quad; depth test on (meshes in front hide impostors),
// depth write off, blended with alpha = coverage (GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA), as
// ImpostorRenderer::render_octahedral draws them. Every function expects the context current.
#pragma once

#include <vector>

#include "libs/render/camera.h"
#include "libs/render/gl_util.h"
#include "libs/render/renderer.h"
#include "libs/render/scene.h"

namespace sylva::render::detail {

class ImpostorDrawer {
 public:
  struct Uploaded {
    std::vector<GLuint> color, normal_depth;  // per set
    GLuint vao = 0, instances = 0;
  };

  ImpostorDrawer() = default;
  ImpostorDrawer(const ImpostorDrawer&) = delete;
  ImpostorDrawer& operator=(const ImpostorDrawer&) = delete;
  void destroy();  // deletes the program (the context must be current); the renderer's destructor calls it

  // Checks and uploads every set's maps (mip levels as the atlas says). Throws RenderError for an
  // atlas without maps, of inconsistent geometry or beyond max_texture_px.
  Uploaded upload(GlObjects& gl, const std::vector<ImpostorSet>& sets, GLint max_texture_px);

  // Draws every instance (state as above; restores depth write on, blending off, texture unit 0).
  void draw(const std::vector<ImpostorSet>& sets, const Uploaded& up, const Camera& camera, float aspect,
            const Lighting& lighting);

 private:
  GLuint program_ = 0;  // linked on first use
};

}  // namespace sylva::render::detail
