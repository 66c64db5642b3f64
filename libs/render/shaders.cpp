// The shader sources (shaders.h); the arrays themselves are generated (shader_sources.cpp.in).
#include "libs/render/shaders.h"

#include "libs/render/impostor_renderer.h"
#include "libs/render/renderer.h"

namespace sylva::render {

const char* octahedral_impostor_vertex_shader() { return detail::kOctahedralImpostorVert; }
const char* octahedral_impostor_fragment_shader() { return detail::kOctahedralImpostorFrag; }

namespace detail {

std::string with_prelude(std::string_view source, std::string_view prelude, std::string_view what) {
  // GLSL wants #version first; the switches go right after it.
  const std::size_t line = source.find('\n');
  if (line == std::string_view::npos || source.compare(0, 9, "#version ") != 0)
    throw RenderError("the " + std::string(what) + " shader does not start with a #version line");
  std::string out(source.substr(0, line + 1));
  out += prelude;
  out += source.substr(line + 1);
  return out;
}

}  // namespace detail
}  // namespace sylva::render
