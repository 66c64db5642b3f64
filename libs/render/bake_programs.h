// Private: the impostor bake's programs (shaders/bake.vert, bake.frag; impostor_renderer.cpp).
//
// One source, a program per variant: MERGED_LINES (the lines of line_merge.h with their extra
// normals), IS_LINES (other lines: their normal turned toward the viewer), HAS_NORMALS,
// HAS_COLORS, HAS_TEXTURE, OPAQUE_LAYER (the packed layer's output, bake_target.h). A variant
// passes on only the varyings it reads: llvmpipe sets up and interpolates every varying of every
// tiny triangle, and a leaf (normals, texture, no colours) needs 6 of the 16 floats (the view
// direction only lines read; measured: docs/performance.md). The variants compute what one
// program with those switches as uniforms computed, to the bit. Every function expects the
// context current.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <utility>

#include "libs/render/gl_util.h"

namespace sylva::render::detail {

// Vertex attribute locations of shaders/bake.vert.
struct BakeAttribute {
  enum : GLuint {
    kPosition = 0,
    kNormal = 1,
    kTexcoord = 2,
    kColor = 3,
    kNormal1 = 4,
    kNormal2 = 5,
    kCopies = 6
  };
};
constexpr std::size_t kMaxRowViews = 64;  // u_views[5 * 64] in shaders/bake.vert: views per draw

// Which bake program draws a primitive.
struct BakeVariant {
  bool merged_lines = false, normals = false, colors = false, texture = false, opaque_layer = false;
  bool lines = false;  // LINES that are not merged_lines
  int key() const {
    return int(merged_lines) | int(normals) << 1 | int(colors) << 2 | int(texture) << 3 |
           int(opaque_layer) << 4 | int(lines) << 5;
  }
};
constexpr int kBakeVariants = 64;

// The vertex and fragment sources of variant `key` (BakeVariant::key()).
std::pair<std::string, std::string> bake_program_sources(int key);

// A context's bake programs, linked when first needed (0 = not yet).
struct BakePrograms {
  std::array<GLuint, kBakeVariants> program{};
  // The program of variant `key`, linked now if it is not yet (RenderUnavailableError when the
  // device cannot compile it).
  GLuint get(int key);
  void destroy();
};

struct BakeUniforms {
  GLint model, normal_matrix, views, base_color, texture, alpha_mode, alpha_cutoff, two_sided, mirrored,
      alpha_scale;
};
BakeUniforms bake_uniforms(GLuint program);

}  // namespace sylva::render::detail
