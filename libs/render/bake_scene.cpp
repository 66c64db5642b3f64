// The impostor bake's scene: uploaded, and drawn over one atlas row (bake_scene.h).
//
// Blended primitives are drawn in file order without sorting: a primitive has one material
// colour, and "over" with equal colours does not depend on order. Blended LINES are drawn with
// each run of coincident segments merged into one line of their composite (line_merge.h), by a
// program variant that carries the copies' normals.
#include "libs/render/bake_scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#include "libs/render/line_merge.h"
#include "libs/render/scene_buffers.h"

namespace sylva::render::detail {
namespace {

const GLenum kAllLayers[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                              GL_COLOR_ATTACHMENT3};

// Binds the row's target, clears it and sets the state the opaque primitives are drawn with.
void begin_bake_row(const BakeTarget& t, const BakeOptions& o, const DeviceLimits& limits) {
  glBindFramebuffer(GL_FRAMEBUFFER, t.draw_fbo);
  glViewport(0, 0, t.width, t.height);
  glDepthMask(GL_TRUE);
  const bool layered = t.layout == BakeLayout::kLayered;
  if (layered) {
    // Every layer to 0 (an integer attachment is cleared by value), then the opaque pass draws
    // into the packed layer only.
    glDrawBuffers(4, kAllLayers);
    const GLfloat zero[4] = {0, 0, 0, 0}, far_depth = 1;
    const GLuint zero_u[4] = {0, 0, 0, 0};
    for (GLint a = 0; a < 3; ++a) glClearBufferfv(GL_COLOR, a, zero);
    glClearBufferuiv(GL_COLOR, 3, zero_u);
    glClearBufferfv(GL_DEPTH, 0, &far_depth);
    const GLenum opaque[4] = {GL_NONE, GL_NONE, GL_NONE, GL_COLOR_ATTACHMENT3};
    glDrawBuffers(4, opaque);
  } else {
    glClearColor(0, 0, 0, 0);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glCullFace(GL_BACK);
  glDisable(GL_BLEND);
  if (o.msaa > 1)
    glEnable(GL_MULTISAMPLE);
  else
    glDisable(GL_MULTISAMPLE);
  glLineWidth(std::clamp(o.line_width_px, limits.line_width_range[0], limits.line_width_range[1]));
}

// The material's uniforms and texture for one primitive, and constant values of the attributes
// it does not have.
void set_bake_material(const Material& m, const std::vector<GLuint>& textures, const Primitive& p,
                       const BakeUniforms& u, const BakeOptions& o) {
  glUniform4fv(u.base_color, 1, m.base_color.data());
  if (m.base_color_texture >= 0 && !p.texcoords.empty()) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, textures[std::size_t(m.base_color_texture)]);
  }
  glUniform1i(u.alpha_mode, m.alpha_mode == AlphaMode::kOpaque ? 0
                            : m.alpha_mode == AlphaMode::kMask ? 1
                                                               : 2);
  glUniform1f(u.alpha_cutoff, m.alpha_cutoff);
  glUniform1i(u.two_sided, p.topology == Topology::kTriangles && m.double_sided);
  glUniform1f(u.alpha_scale, p.topology == Topology::kLines ? std::clamp(o.line_alpha_scale, 0.f, 1.f) : 1.f);
  if (p.normals.empty()) glVertexAttrib3f(BakeAttribute::kNormal, 0, 0, 1);
  if (p.texcoords.empty()) glVertexAttrib2f(BakeAttribute::kTexcoord, 0, 0);
  if (p.colors.empty()) glVertexAttrib4f(BakeAttribute::kColor, 1, 1, 1, 1);
}

}  // namespace

BakeLayout choose_layout(const Scene& scene, const BakeOptions& o) {
  if (o.msaa != 1 || !o.pack_opaque) return BakeLayout::kBlended;
  if (o.line_alpha_scale < 1)
    for (const Mesh& mesh : scene.meshes)
      for (const Primitive& p : mesh.primitives)
        if (p.topology == Topology::kLines && !blended(scene, p)) return BakeLayout::kBlended;
  return BakeLayout::kLayered;
}

std::vector<BakePrimitive> upload_bake_scene(GlObjects& gl, const Scene& scene, BakeLayout layout) {
  std::vector<BakePrimitive> out;
  for (const Mesh& mesh : scene.meshes) {
    if (mesh.instances.empty()) continue;
    for (const Primitive& p : mesh.primitives) {
      check_primitive(scene, p, /*with_sizes_and_copies=*/false);
      if (p.indices.empty() || p.topology == Topology::kPoints) continue;  // trees have no points
      BakePrimitive bp;
      bp.source = &p;
      bp.mesh = &mesh;
      bp.index_count = GLsizei(p.indices.size());
      bp.blend = blended(scene, p);
      BakeVariant variant;
      variant.merged_lines = bp.blend && p.topology == Topology::kLines;
      variant.normals = !p.normals.empty();
      variant.colors = !p.colors.empty();
      variant.texture = p.material >= 0 && scene.materials[std::size_t(p.material)].base_color_texture >= 0 &&
                        !p.texcoords.empty();
      variant.opaque_layer = layout == BakeLayout::kLayered && !bp.blend;
      variant.lines = p.topology == Topology::kLines && !variant.merged_lines;
      bp.variant = variant.key();
      bp.vao = gl.vertex_array();
      glBindVertexArray(bp.vao);
      auto attach = [&](GLuint location, GLuint buffer, GLint comps) {
        glBindBuffer(GL_ARRAY_BUFFER, buffer);
        glEnableVertexAttribArray(location);
        glVertexAttribPointer(location, comps, GL_FLOAT, GL_FALSE, 0, nullptr);
      };
      if (bp.blend && p.topology == Topology::kLines) {
        // Coincident blended lines as one line of their composite (line_merge.h).
        const MergedLines m = merge_coincident_lines(p);
        bp.indexed = false;
        bp.index_count = GLsizei(m.positions.size());
        attach(BakeAttribute::kPosition, upload_array(gl, GL_ARRAY_BUFFER, m.positions), 3);
        if (!p.normals.empty()) {
          attach(BakeAttribute::kNormal, upload_array(gl, GL_ARRAY_BUFFER, m.normals[0]), 3);
          attach(BakeAttribute::kNormal1, upload_array(gl, GL_ARRAY_BUFFER, m.normals[1]), 3);
          attach(BakeAttribute::kNormal2, upload_array(gl, GL_ARRAY_BUFFER, m.normals[2]), 3);
        }
        if (!m.texcoords.empty())
          attach(BakeAttribute::kTexcoord, upload_array(gl, GL_ARRAY_BUFFER, m.texcoords), 2);
        if (!m.colors.empty()) attach(BakeAttribute::kColor, upload_array(gl, GL_ARRAY_BUFFER, m.colors), 4);
        attach(BakeAttribute::kCopies, upload_array(gl, GL_ARRAY_BUFFER, m.copies), 1);
        glBindVertexArray(0);
        out.push_back(bp);
        continue;
      }
      attach(BakeAttribute::kPosition, upload_array(gl, GL_ARRAY_BUFFER, p.positions), 3);
      if (!p.normals.empty()) attach(BakeAttribute::kNormal, upload_array(gl, GL_ARRAY_BUFFER, p.normals), 3);
      if (!p.texcoords.empty())
        attach(BakeAttribute::kTexcoord, upload_array(gl, GL_ARRAY_BUFFER, p.texcoords), 2);
      if (!p.colors.empty()) attach(BakeAttribute::kColor, upload_array(gl, GL_ARRAY_BUFFER, p.colors), 4);
      upload_array(gl, GL_ELEMENT_ARRAY_BUFFER, p.indices);
      glBindVertexArray(0);
      out.push_back(bp);
    }
  }
  // Opaque and masked first, then blended; each group in file order.
  std::stable_partition(out.begin(), out.end(), [](const BakePrimitive& p) { return !p.blend; });
  return out;
}

void draw_bake_row(const Scene& scene, const std::vector<BakePrimitive>& prims,
                   const std::vector<GLuint>& textures, const BakePrograms& programs,
                   const std::array<BakeUniforms, kBakeVariants>& uniforms, GLsizei count,
                   const BakeTarget& t, const BakeOptions& o, const DeviceLimits& limits) {
  begin_bake_row(t, o, limits);
  const bool layered = t.layout == BakeLayout::kLayered;
  bool blending = false;
  for (const BakePrimitive& bp : prims) {
    const Primitive& p = *bp.source;
    const BakeUniforms& u = uniforms[std::size_t(bp.variant)];
    glUseProgram(programs.program[std::size_t(bp.variant)]);
    if (bp.blend && !blending) {
      blending = true;
      if (layered) glDrawBuffers(3, kAllLayers);  // the blended layers
      glEnable(GL_BLEND);
      glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
      glDepthMask(GL_FALSE);
    }
    static const Material kDefault;
    const Material& m = p.material >= 0 ? scene.materials[std::size_t(p.material)] : kDefault;
    set_bake_material(m, textures, p, u, o);
    const bool triangles = p.topology == Topology::kTriangles;
    glBindVertexArray(bp.vao);
    for (const Mat4& model : bp.mesh->instances) {
      Eigen::Matrix3f n = model.topLeftCorner<3, 3>();
      const bool mirrored = n.determinant() < 0;
      if (std::abs(n.determinant()) > 1e-20f) n = n.inverse().transpose().eval();
      glUniform1i(u.mirrored, mirrored);
      // Single-sided triangles: back faces culled, as the scene renderer culls them.
      if (triangles && !m.double_sided) {
        glEnable(GL_CULL_FACE);
        glFrontFace(mirrored ? GL_CW : GL_CCW);
      } else {
        glDisable(GL_CULL_FACE);
      }
      glUniformMatrix4fv(u.model, 1, GL_FALSE, model.data());
      glUniformMatrix3fv(u.normal_matrix, 1, GL_FALSE, n.data());
      if (bp.indexed)
        glDrawElementsInstanced(gl_mode(p.topology), bp.index_count, GL_UNSIGNED_INT, nullptr, count);
      else
        glDrawArraysInstanced(gl_mode(p.topology), 0, bp.index_count, count);
    }
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glFrontFace(GL_CCW);
}
}  // namespace sylva::render::detail
