// The impostor bake's programs (bake_programs.h).
#include "libs/render/bake_programs.h"

#include "libs/render/shaders.h"

namespace sylva::render::detail {

std::pair<std::string, std::string> bake_program_sources(int key) {
  std::string switches;
  for (auto [bit, name] : {std::pair{1, "MERGED_LINES"},
                           {2, "HAS_NORMALS"},
                           {4, "HAS_COLORS"},
                           {8, "HAS_TEXTURE"},
                           {16, "OPAQUE_LAYER"},
                           {32, "IS_LINES"}})
    switches += std::string("#define ") + name + ((key & bit) ? " 1\n" : " 0\n");
  return {with_prelude(kBakeVert, switches, "impostor bake vertex"),
          with_prelude(kBakeFrag, switches, "impostor bake fragment")};
}

GLuint BakePrograms::get(int key) {
  GLuint& p = program[std::size_t(key)];
  if (!p) {
    const auto [vertex, fragment] = bake_program_sources(key);
    p = link_program(vertex.c_str(), fragment.c_str(), "impostor bake (variant " + std::to_string(key) + ")");
  }
  return p;
}

void BakePrograms::destroy() {
  for (GLuint& p : program) {
    if (p) glDeleteProgram(p);
    p = 0;
  }
}

BakeUniforms bake_uniforms(GLuint program) {
  auto u = [&](const char* n) { return glGetUniformLocation(program, n); };
  return {u("u_model"),      u("u_normal_matrix"), u("u_views[0]"),  u("u_base_color"), u("u_texture"),
          u("u_alpha_mode"), u("u_alpha_cutoff"),  u("u_two_sided"), u("u_mirrored"),   u("u_alpha_scale")};
}

}  // namespace sylva::render::detail
