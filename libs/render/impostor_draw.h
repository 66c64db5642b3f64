// Private: drawing Scene::impostors inside the scene renderer (gl_renderer.cpp), into the same
// target and depth buffer as the meshes, with the reference shader (shaders/octahedral_impostor.*,
// the one `sylva impostorcheck` proves; impostor_renderer.h draws impostors alone with it).
//
// Per view: every instance of every set sorted far to near by the view depth of its sphere centre
// (ties: set, then instance order), drawn in runs of consecutive instances of one set, each run
// one instanced draw of a camera-facing quad; depth test on (meshes in front hide impostors),
// depth write off, blended with alpha = coverage (GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA), as
// ImpostorRenderer::render_octahedral draws them. Every function expects the context current.
//
// The maps (two RGBA8 textures with mip levels per species, 4096 or 6144 px, and the two below:
// ~1.0 s for forest_celba's three species, docs/performance.md "Forest", "Levers kept") stay
// uploaded between calls while their atlas lives: a drawer keeps each
// atlas's textures with a weak reference to it and deletes them once the atlas is gone (checked
// at every upload) or when the drawer is destroyed.
//
// One program per parallax step count, the count a compile-time constant of it (the shader's
// `uniform int u_parallax_steps` declared `const`): llvmpipe's JIT code then has no loop for flat
// frames and a fixed trip count otherwise. The pixels are the uniform's.
//
// The programs turn on the reference shader's two exact options (its pixels, byte for byte;
// docs/renderer.md "Impostor march"): SYLVA_DEPTH_COVERAGE, the march's depth and coverage from
// one RG8 texture (a third map per atlas, level 0 only: 2 bytes a texel), and
// SYLVA_EMPTY_DISTANCE, the discard before the march of fragments that would read nothing stored
// (impostor_empty_distance, impostor_atlas.h: one byte per 4 x 4 texels). Both maps are uploaded
// and kept with the atlas's maps. A third exact option, SYLVA_SCENE_DEPTH, is on when draw() is
// given the scene's per-pixel farthest depth (the renderer's hybrid antialiasing): the discard
// before the march of fragments every sample of which the meshes hide.
#pragma once

#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "libs/render/camera.h"
#include "libs/render/gl_util.h"
#include "libs/render/renderer.h"
#include "libs/render/scene.h"

namespace sylva::render::detail {

// The reference shader's per-impostor uniforms (frames, hemi, sphere, frame extent, padding,
// parallax steps clamped to 0..64, atlas size) for `g` on `program`, which must be in use.
void set_impostor_uniforms(GLuint program, const ImpostorGeometry& g, int parallax_steps);

class ImpostorDrawer {
 public:
  struct Uploaded {
    std::vector<GLuint> color, normal_depth, empty_distance, depth_coverage;  // per set
    GLuint vao = 0, instances = 0;
  };

  ImpostorDrawer() = default;
  ImpostorDrawer(const ImpostorDrawer&) = delete;
  ImpostorDrawer& operator=(const ImpostorDrawer&) = delete;
  // Deletes the program and the kept maps (the context must be current); the renderer's
  // destructor calls it.
  void destroy();

  // Checks every set's atlas and uploads its maps (mip levels as the atlas says) unless they are
  // still uploaded from an earlier call. Throws RenderError for an atlas without maps, of
  // inconsistent geometry or beyond max_texture_px.
  // The programs draw() will use are linked here (with SYLVA_SCENE_DEPTH when `scene_depth`).
  Uploaded upload(GlObjects& gl, const std::vector<ImpostorSet>& sets, GLint max_texture_px,
                  bool scene_depth = false);

  // Atlases whose maps are uploaded (for tests).
  std::size_t kept() const { return kept_.size(); }

  // Draws every instance (state as above; restores depth write on, blending off, texture unit 0).
  // With `scene_depth` != 0, the programs also turn on the shader's SYLVA_SCENE_DEPTH: that
  // texture (target size, R32F, complete for texelFetch) holds per pixel the greatest depth of the
  // target's samples there, and fragments every sample of which is hidden are not marched.
  void draw(const std::vector<ImpostorSet>& sets, const Uploaded& up, const Camera& camera, float aspect,
            const Lighting& lighting, GLuint scene_depth = 0);

 private:
  struct Kept {
    std::weak_ptr<const ImpostorAtlas> atlas;
    GLuint color = 0, normal_depth = 0, empty_distance = 0, depth_coverage = 0;
  };
  // The program for `steps` (clamped to 0..64), with or without SYLVA_SCENE_DEPTH, linked on
  // first use.
  GLuint program(int steps, bool scene_depth);

  std::map<std::pair<int, bool>, GLuint> programs_;  // by (parallax steps, scene depth)
  std::vector<Kept> kept_;
};

}  // namespace sylva::render::detail
