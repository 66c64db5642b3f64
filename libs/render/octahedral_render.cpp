// An impostor's instances alone in a view (octahedral_render.h).
#include "libs/render/octahedral_render.h"

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>

#include "libs/render/impostor_atlas.h"
#include "libs/render/impostor_draw.h"

namespace sylva::render::detail {
namespace {

struct DrawTarget {
  GLuint draw_fbo = 0, resolve_fbo = 0;  // resolve_fbo == draw_fbo without multisampling
};

void validate_draw(const OctahedralImpostor& imp, const RenderOptions& o, const DeviceLimits& limits) {
  const GLint max_texture_size = limits.max_texture_size;
  check_target_size("image", o.width, o.height, o.msaa, limits);
  if (o.background.a != 0 && o.background.a != 255)
    throw RenderError("background alpha must be 0 (transparent) or 255 (opaque)");
  const ImpostorGeometry& g = imp.geometry;
  const int atlas = g.frames_per_side * g.frame_px;
  if (g.frames_per_side < 2 || g.frame_px < 1 || atlas > max_texture_size)
    throw RenderError("impostor atlas of " + std::to_string(g.frames_per_side) + " x " +
                      std::to_string(g.frame_px) +
                      " px frames is not drawable here (2 or more frames, at most " +
                      std::to_string(max_texture_size) + " px)");
  for (const image::Image* m : {&imp.color, &imp.normal_depth})
    if (m->width() != atlas || m->height() != atlas)
      throw RenderError("impostor maps must be " + std::to_string(atlas) + "x" + std::to_string(atlas) +
                        " pixels, got " + std::to_string(m->width()) + "x" + std::to_string(m->height()));
  if (!(g.radius > 0) || !(g.half_extent >= g.radius) || g.padding_px < 0 || 2 * g.padding_px >= g.frame_px)
    throw RenderError(
        "impostor geometry is inconsistent (radius > 0, half extent >= radius, padding < frame / 2)");
}

DrawTarget make_draw_target(GlObjects& gl, const RenderOptions& o) {
  auto attach = [&](GLuint fbo, GLenum attachment, GLenum format, int samples) {
    attach_renderbuffer(gl, fbo, attachment, format, samples, o.width, o.height);
  };
  DrawTarget t;
  t.draw_fbo = gl.framebuffer();
  attach(t.draw_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, o.msaa);
  attach(t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, o.msaa);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("cannot create the impostor target");
  t.resolve_fbo = t.draw_fbo;
  if (o.msaa > 1) {
    t.resolve_fbo = gl.framebuffer();
    attach(t.resolve_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, 1);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("cannot create the impostor resolve target");
  }
  return t;
}

// A map, premultiplied as the reference shader samples it, uploaded with its mip levels.
GLuint upload_atlas(GlObjects& gl, const image::Image& img, bool srgb, int mip_levels) {
  const GLuint id = gl.texture();
  glBindTexture(GL_TEXTURE_2D, id);
  upload_mipmapped_rgba8(img.bytes().data(), img.width(), img.height(), srgb, mip_levels);
  return id;
}

// One quad (two triangles), instanced per impostor: corners at location 0, the instances'
// matrices at 1-4 (replaced per view by sort_instances).
GLuint upload_quads(GlObjects& gl, const OctahedralImpostor& imp) {
  const std::vector<float> corners = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
  std::vector<float> models;
  for (const Mat4& m : imp.instances) models.insert(models.end(), m.data(), m.data() + 16);
  const GLuint vao = gl.vertex_array();
  glBindVertexArray(vao);
  glBindBuffer(GL_ARRAY_BUFFER, upload_array(gl, GL_ARRAY_BUFFER, corners));
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glBindBuffer(GL_ARRAY_BUFFER, upload_array(gl, GL_ARRAY_BUFFER, models));
  for (GLuint c = 0; c < 4; ++c) {
    glEnableVertexAttribArray(1 + c);
    glVertexAttribPointer(1 + c, 4, GL_FLOAT, GL_FALSE, 16 * sizeof(float),
                          reinterpret_cast<const void*>(std::uintptr_t(c * 4 * sizeof(float))));
    glVertexAttribDivisor(1 + c, 1);
  }
  return vao;
}

// Instances far to near (by the view depth of their centre; ties keep their order), so that
// blended instances composite correctly: their matrices uploaded in that order into `vao`.
void sort_instances(const OctahedralImpostor& imp, const Camera& cam, GlObjects& gl, GLuint vao) {
  if (imp.instances.size() < 2) return;
  const Mat4 view = cam.view_matrix();
  std::vector<std::pair<float, std::size_t>> keys;
  for (std::size_t i = 0; i < imp.instances.size(); ++i) {
    const Vec3 w = (imp.instances[i] * imp.geometry.center.homogeneous()).hnormalized();
    keys.push_back({(view * w.homogeneous())(2), i});  // more negative = farther
  }
  std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<float> models;
  for (const auto& k : keys)
    models.insert(models.end(), imp.instances[k.second].data(), imp.instances[k.second].data() + 16);
  glBindVertexArray(vao);
  const GLuint b = upload_array(gl, GL_ARRAY_BUFFER, models);
  for (GLuint c = 0; c < 4; ++c) {
    glVertexAttribPointer(1 + c, 4, GL_FLOAT, GL_FALSE, 16 * sizeof(float),
                          reinterpret_cast<const void*>(std::uintptr_t(c * 4 * sizeof(float))));
  }
  (void)b;
}

// The program's per-impostor uniforms and maps (texture units 0 and 1).
void use_program(GLuint program, const OctahedralImpostor& imp, const RenderOptions& o,
                 const ImpostorDrawOptions& draw, GLuint color, GLuint normal) {
  glUseProgram(program);
  auto u = [&](const char* n) { return glGetUniformLocation(program, n); };
  set_impostor_uniforms(program, imp.geometry, draw.parallax_steps);
  glUniform3fv(u("u_ambient"), 1, o.lighting.ambient.data());
  glUniform3fv(u("u_light_color"), 1, o.lighting.light_color.data());
  const Vec3 l =
      o.lighting.direction_to_light.norm() > 0 ? o.lighting.direction_to_light.normalized() : Vec3::UnitY();
  glUniform3fv(u("u_light_dir"), 1, l.data());
  glUniform1i(u("u_color"), 0);
  glUniform1i(u("u_normal_depth"), 1);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, color);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, normal);
  glActiveTexture(GL_TEXTURE0);
}

// One view: cleared to the background, every instance blended over it, read back.
image::Image draw_view(GLuint program, const OctahedralImpostor& imp, const Camera& cam,
                       const RenderOptions& o, const DrawTarget& target, GlObjects& gl, GLuint vao) {
  auto u = [&](const char* n) { return glGetUniformLocation(program, n); };
  const float aspect = float(o.width) / float(o.height);
  glBindFramebuffer(GL_FRAMEBUFFER, target.draw_fbo);
  glViewport(0, 0, o.width, o.height);
  clear_to_background(o.background);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  if (o.msaa > 1)
    glEnable(GL_MULTISAMPLE);
  else
    glDisable(GL_MULTISAMPLE);
  glUniformMatrix4fv(u("u_view"), 1, GL_FALSE, cam.view_matrix().data());
  glUniformMatrix4fv(u("u_proj"), 1, GL_FALSE, cam.projection_matrix(aspect).data());
  glUniform3fv(u("u_eye"), 1, cam.eye.data());
  sort_instances(imp, cam, gl, vao);
  glDrawArraysInstanced(GL_TRIANGLES, 0, 6, GLsizei(imp.instances.size()));
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  if (target.resolve_fbo != target.draw_fbo) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.draw_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.resolve_fbo);
    glBlitFramebuffer(0, 0, o.width, o.height, 0, 0, o.width, o.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  // Over a transparent background the target holds premultiplied colour.
  return read_rgba8(target.resolve_fbo, o.width, o.height, o.background.a == 0);
}

}  // namespace

std::vector<image::Image> render_octahedral_views(GLuint program, const DeviceLimits& limits,
                                                  const OctahedralImpostor& imp,
                                                  std::span<const Camera> cameras, const RenderOptions& o,
                                                  const ImpostorDrawOptions& draw) {
  validate_draw(imp, o, limits);
  const ImpostorGeometry& g = imp.geometry;
  GlObjects gl;
  glGetError();
  const DrawTarget target = make_draw_target(gl, o);
  // The maps as the reference shader samples them (shaders/octahedral_impostor.frag): colour
  // rgb = sRGB(linear(rgb) * a), normal rgb = encoded normal * a, alpha and depth unchanged.
  image::Image color = imp.color, normal_depth = imp.normal_depth;
  premultiply_impostor_maps(color.bytes(), normal_depth.bytes());
  const GLuint color_map = upload_atlas(gl, color, true, g.mip_levels);
  const GLuint normal_map = upload_atlas(gl, normal_depth, false, g.mip_levels);
  const GLuint vao = upload_quads(gl, imp);
  check_gl("impostor upload");
  use_program(program, imp, o, draw, color_map, normal_map);
  std::vector<image::Image> images;
  for (const Camera& cam : cameras) {
    images.push_back(draw_view(program, imp, cam, o, target, gl, vao));
    check_gl("impostor drawing");
  }
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return images;
}

}  // namespace sylva::render::detail
