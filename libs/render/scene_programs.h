// Private: the scene renderer's shader programs (shaders/scene.vert, scene.frag) and the state of
// one draw (gl_renderer.cpp).
//
// The fragment shader's draw state (texture or not, alpha mode, lit, normals, double-sided,
// culled in the shader, round points, line copies) is not uniforms but constants of one program
// per state used: llvmpipe's JIT code then carries no branch on it. The uniforms every program of
// a view shares are set on a program before its first draw of the view. Every function expects
// the context current.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "libs/render/gl_util.h"
#include "libs/render/scene.h"

namespace sylva::render::detail {

// Vertex attribute locations of shaders/scene.vert.
struct SceneAttribute {
  enum : GLuint {
    kPosition = 0,
    kNormal = 1,
    kTexcoord = 2,
    kColor = 3,
    kSize = 4,
    kModel = 5,         // mat4: locations 5-8
    kNormalMatrix = 9,  // mat3: locations 9-11
    kCopies = 12
  };
};
// Floats per instance: the model matrix (16, column-major), then the normal matrix (9).
constexpr int kInstanceFloats = 16 + 9;

// What a draw's fragment shader is specialised for (shaders/scene_draw_state.glsl).
struct DrawState {
  bool textured = false;
  int alpha_mode = 0;  // 0 opaque, 1 mask, 2 blend
  bool lit = false, has_normals = false, two_sided = false, cull_in_shader = false, round_points = false;
  bool line_copies = false;
  int key() const {
    return int(textured) | alpha_mode << 1 | int(lit) << 3 | int(has_normals) << 4 | int(two_sided) << 5 |
           int(cull_in_shader) << 6 | int(round_points) << 7 | int(line_copies) << 8;
  }
};

// The fragment shader's source for `st`: scene.frag with the state's constants after #version.
std::string scene_fragment_source(const DrawState& st);

// The uniforms every program of one view shares.
struct ViewUniforms {
  Mat4 view = Mat4::Identity(), proj = Mat4::Identity();
  float viewport_height = 0, default_point_size = 0, min_point_size = 0;  // pixels of the target
  Vec3 ambient = Vec3::Zero(), light_color = Vec3::Zero(),
       light_dir = Vec3::UnitY();  // unit, toward the light
};

class ScenePrograms {
 public:
  ScenePrograms() = default;
  ScenePrograms(const ScenePrograms&) = delete;
  ScenePrograms& operator=(const ScenePrograms&) = delete;
  // Deletes every program (the renderer's destructor).
  void destroy();

  // Starts a view: every program gets `v` before its first draw of it; no program is current.
  void begin_view(const ViewUniforms& v);
  // Another program was made current (the impostor drawer's).
  void forget_current() { current_ = 0; }

  // Material and per-primitive state for one draw of `p` of `scene`: the program of its draw
  // state (linked on first use; a compile or link failure throws RenderUnavailableError) with the
  // view's uniforms, the material's uniforms and texture (`textures`: the scene's, uploaded), face
  // culling, and constant values of the attributes `p` does not have. `mirrored_instances`: some
  // instance of its mesh mirrors (its single-sided triangles are culled in the shader).
  void set_primitive_state(const Scene& scene, const std::vector<GLuint>& textures, const Primitive& p,
                           bool mirrored_instances);

 private:
  struct Uniforms {
    GLint view, proj, viewport_height, default_point_size, min_point_size, base_color, texture, alpha_cutoff,
        ambient, light_color, light_dir;
  };
  // One linked program and which view's uniforms it holds.
  struct Program {
    GLuint id = 0;
    Uniforms u{};
    std::uint64_t view = 0;
  };

  static Uniforms uniforms(GLuint program);
  // Makes the program for `st` current with this view's uniforms.
  const Program& use(const DrawState& st);

  std::map<int, Program> programs_;  // by DrawState::key()
  GLuint current_ = 0;               // the program in use within a view, 0 = unknown
  ViewUniforms view_;
  std::uint64_t view_serial_ = 0;  // views begun so far: a program whose `view` differs needs view_
};

}  // namespace sylva::render::detail
