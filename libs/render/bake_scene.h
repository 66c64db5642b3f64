// Private: the scene an impostor bake draws (impostor_renderer.cpp), uploaded once per context
// and drawn over one atlas row at a time: one instanced draw per primitive over the row's views
// (bake_rows.h), opaque and masked primitives first (depth test and write), then blended ones
// (depth test, no write, alpha over), as the scene renderer's passes. Every function expects the
// context current.
#pragma once

#include <array>
#include <vector>

#include "libs/render/bake_programs.h"
#include "libs/render/bake_target.h"
#include "libs/render/gl_util.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/scene.h"

namespace sylva::render::detail {

struct BakePrimitive {
  const Primitive* source = nullptr;
  const Mesh* mesh = nullptr;
  GLuint vao = 0;
  GLsizei index_count = 0;  // indices, or vertices when not indexed
  int variant = 0;          // BakeVariant::key()
  bool indexed = true;      // false: merged lines (line_merge.h), drawn as arrays
  bool blend = false;
};

// kLayered for msaa 1 with BakeOptions::pack_opaque, unless an opaque or masked line carries a
// fractional alpha (line_alpha_scale < 1): the packed layer has no coverage but covered or not.
BakeLayout choose_layout(const Scene& scene, const BakeOptions& o);

// Every instanced primitive of `scene` but points (trees have none) uploaded into `gl`, opaque
// and masked first, then blended; each group in file order. Throws RenderError("invalid
// primitive in scene '<source>': ...") for attribute arrays, indices, materials or textures out
// of range.
std::vector<BakePrimitive> upload_bake_scene(GlObjects& gl, const Scene& scene, BakeLayout layout);

// Clears `t` and draws `prims` into it, every primitive instanced over the row's `count` views
// (the programs already hold the row's u_views). `textures`: the scene's, uploaded;
// `uniforms`: of each variant `prims` uses. Leaves depth write on, blending and culling off.
void draw_bake_row(const Scene& scene, const std::vector<BakePrimitive>& prims,
                   const std::vector<GLuint>& textures, const BakePrograms& programs,
                   const std::array<BakeUniforms, kBakeVariants>& uniforms, GLsizei count,
                   const BakeTarget& t, const BakeOptions& o, const DeviceLimits& limits);

}  // namespace sylva::render::detail
