// The scene renderer's programs and per-draw state (scene_programs.h).
#include "libs/render/scene_programs.h"

#include <cstdio>

#include "libs/render/shaders.h"

namespace sylva::render::detail {

std::string scene_fragment_source(const DrawState& st) {
  auto b = [](bool v) { return v ? "true" : "false"; };
  char state[640];
  std::snprintf(state, sizeof state, kSceneDrawStateGlsl, b(st.textured), st.alpha_mode, b(st.lit),
                b(st.has_normals), b(st.two_sided), b(st.cull_in_shader), b(st.round_points),
                b(st.line_copies));
  return with_prelude(kSceneFrag, state, "scene fragment");
}

void ScenePrograms::destroy() {
  for (const auto& [key, program] : programs_) glDeleteProgram(program.id);
  programs_.clear();
}

void ScenePrograms::begin_view(const ViewUniforms& v) {
  view_ = v;
  ++view_serial_;
  current_ = 0;
}

ScenePrograms::Uniforms ScenePrograms::uniforms(GLuint program) {
  auto u = [&](const char* n) { return glGetUniformLocation(program, n); };
  return {u("u_view"),           u("u_proj"),        u("u_viewport_height"), u("u_default_point_size"),
          u("u_min_point_size"), u("u_base_color"),  u("u_texture"),         u("u_alpha_cutoff"),
          u("u_ambient"),        u("u_light_color"), u("u_light_dir")};
}

const ScenePrograms::Program& ScenePrograms::use(const DrawState& st) {
  auto it = programs_.find(st.key());
  if (it == programs_.end()) {
    Program p;
    p.id = link_program(kSceneVert, scene_fragment_source(st).c_str(), "scene");
    p.u = uniforms(p.id);
    it = programs_.emplace(st.key(), p).first;
  }
  Program& p = it->second;
  if (current_ != p.id) {
    glUseProgram(p.id);
    current_ = p.id;
  }
  if (p.view != view_serial_) {
    const ViewUniforms& v = view_;
    glUniformMatrix4fv(p.u.view, 1, GL_FALSE, v.view.data());
    glUniformMatrix4fv(p.u.proj, 1, GL_FALSE, v.proj.data());
    glUniform1f(p.u.viewport_height, v.viewport_height);
    glUniform1f(p.u.default_point_size, v.default_point_size);
    glUniform1f(p.u.min_point_size, v.min_point_size);
    glUniform1i(p.u.texture, 0);
    glUniform3fv(p.u.ambient, 1, v.ambient.data());
    glUniform3fv(p.u.light_color, 1, v.light_color.data());
    glUniform3fv(p.u.light_dir, 1, v.light_dir.data());
    p.view = view_serial_;
  }
  return p;
}

void ScenePrograms::set_primitive_state(const Scene& scene, const std::vector<GLuint>& textures,
                                        const Primitive& p, bool mirrored_instances) {
  static const Material kDefault;
  const Material& m = p.material >= 0 ? scene.materials[std::size_t(p.material)] : kDefault;
  DrawState st;
  st.textured = m.base_color_texture >= 0 && !p.texcoords.empty();
  st.alpha_mode = m.alpha_mode == AlphaMode::kOpaque ? 0 : m.alpha_mode == AlphaMode::kMask ? 1 : 2;
  st.has_normals = !p.normals.empty();
  // LINES are unlit, as three.js draws them (GLTFLoader: LineBasicMaterial = base colour x
  // COLOR_0): glTF defines no lighting for lines, and the verifier must see what clients do.
  st.lit =
      !m.unlit && p.topology != Topology::kLines && (p.topology == Topology::kTriangles || st.has_normals);
  const bool triangles = p.topology == Topology::kTriangles;
  st.two_sided = triangles && m.double_sided;
  st.round_points = p.topology == Topology::kPoints;
  st.line_copies = p.topology == Topology::kLines && !p.copies.empty();
  // Back faces of single-sided triangles are culled; GL's cull state is per draw, so a mesh
  // with a mirrored instance culls in the shader instead (front = CW there).
  const bool cull = triangles && !m.double_sided;
  st.cull_in_shader = cull && mirrored_instances;
  const Program& program = use(st);
  glUniform4fv(program.u.base_color, 1, m.base_color.data());
  glUniform1f(program.u.alpha_cutoff, m.alpha_cutoff);
  if (st.textured) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, textures[std::size_t(m.base_color_texture)]);
  }
  if (cull && !mirrored_instances) {
    glEnable(GL_CULL_FACE);
  } else {
    glDisable(GL_CULL_FACE);
  }
  // Constant values for the attributes this primitive does not have.
  if (p.normals.empty()) glVertexAttrib3f(SceneAttribute::kNormal, 0, 0, 1);
  if (p.texcoords.empty()) glVertexAttrib2f(SceneAttribute::kTexcoord, 0, 0);
  if (p.colors.empty()) glVertexAttrib4f(SceneAttribute::kColor, 1, 1, 1, 1);
  if (p.sizes.empty() || p.topology != Topology::kPoints) glVertexAttrib1f(SceneAttribute::kSize, -1.f);
  if (!st.line_copies) glVertexAttrib1f(SceneAttribute::kCopies, 1.f);
}

}  // namespace sylva::render::detail
