// The impostor bake's targets and read-back (bake_target.h).
#include "libs/render/bake_target.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>

#include "libs/render/bake_layers.h"

namespace sylva::render::detail {

BakeTarget make_bake_target(GlObjects& gl, int w, int h, int msaa, BakeLayout layout) {
  BakeTarget t;
  t.width = w;
  t.height = h;
  t.layout = layout;
  const GLenum formats[3] = {GL_RGBA8, GL_RGBA16, GL_RGBA16};
  auto attach = [&](GLuint fbo, GLenum attachment, GLenum format, int samples) {
    attach_renderbuffer(gl, fbo, attachment, format, samples, w, h);
  };
  const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  t.draw_fbo = gl.framebuffer();
  if (layout == BakeLayout::kLayered) {
    // The blended layers (colour, normal, depth: RGBA16) and the packed opaque layer.
    for (int a = 0; a < 3; ++a) attach(t.draw_fbo, bufs[a], GL_RGBA16, 1);
    attach(t.draw_fbo, GL_COLOR_ATTACHMENT3, GL_RGBA16UI, 1);
    attach(t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, 1);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("cannot create a " + std::to_string(w) + "x" + std::to_string(h) + " bake target");
    t.resolve_fbo = t.draw_fbo;
    return t;
  }
  for (int a = 0; a < 3; ++a) attach(t.draw_fbo, bufs[a], formats[a], msaa);
  attach(t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, msaa);
  glDrawBuffers(3, bufs);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("cannot create a " + std::to_string(w) + "x" + std::to_string(h) + " bake target");
  t.resolve_fbo = t.draw_fbo;
  if (msaa > 1) {
    t.resolve_fbo = gl.framebuffer();
    for (int a = 0; a < 3; ++a) attach(t.resolve_fbo, bufs[a], formats[a], 1);
    glDrawBuffers(3, bufs);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("cannot create the bake resolve target");
  }
  return t;
}

void read_bake_row(const BakeTarget& t, int band_y, RowPixels& px, BakedMaps& out) {
  const std::size_t n = std::size_t(t.width) * std::size_t(t.height);
  if (px.color.size() < n * 4) {
    px.color.resize(n * 4);
    px.normal.resize(n * 4);
    px.depth.resize(n * 4);
  }
  const std::vector<std::uint8_t>& color = px.color;
  const std::vector<std::uint16_t>&normal = px.normal, &depth = px.depth;
  for (int a = 0; a < 3; ++a) {
    const GLenum att = GL_COLOR_ATTACHMENT0 + GLenum(a);
    if (t.resolve_fbo != t.draw_fbo) {
      glBindFramebuffer(GL_READ_FRAMEBUFFER, t.draw_fbo);
      glReadBuffer(att);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolve_fbo);
      glDrawBuffers(1, &att);
      glBlitFramebuffer(0, 0, t.width, t.height, 0, 0, t.width, t.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.resolve_fbo);
    glReadBuffer(att);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (a == 0) {
      glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, px.color.data());
    } else {
      glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_SHORT,
                   a == 1 ? px.normal.data() : px.depth.data());
    }
  }
  if (t.resolve_fbo != t.draw_fbo) {
    const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolve_fbo);
    glDrawBuffers(3, bufs);
  }
  auto& cb = out.color.bytes();
  auto& nb = out.normal_depth.bytes();
  const std::size_t stride = std::size_t(out.color.width()) * 4;
  for (int y = 0; y < t.height; ++y) {
    const std::size_t src_row =
        std::size_t(t.height - 1 - y) * std::size_t(t.width) * 4;  // GL rows run bottom up
    const std::size_t dst_row = std::size_t(band_y + y) * stride;
    for (int x = 0; x < t.width; ++x) {
      const std::size_t s = src_row + std::size_t(x) * 4, d = dst_row + std::size_t(x) * 4;
      const int a8 = color[s + 3];
      if (a8 == 0) continue;
      // Values are coverage-weighted; the coverage is the attachments' common alpha.
      const double an = normal[s + 3] / 65535.0, ad = depth[s + 3] / 65535.0;
      for (int c = 0; c < 3; ++c) cb[d + c] = std::uint8_t(std::min(255, (color[s + c] * 255 + a8 / 2) / a8));
      cb[d + 3] = std::uint8_t(a8);
      // The mean of the covered samples' normals, not renormalised: its length says how much
      // they spread, and the shader lights with it (mean(n.l) = mean(n).l).
      Eigen::Vector3d nv(normal[s] / 65535.0, normal[s + 1] / 65535.0, normal[s + 2] / 65535.0);
      nv = (nv / std::max(an, 1e-9)) * 2.0 - Eigen::Vector3d::Ones();
      if (nv.norm() > 1) nv.normalize();
      for (int c = 0; c < 3; ++c)
        nb[d + c] = std::uint8_t(std::lround(std::clamp((nv[c] * 0.5 + 0.5) * 255.0, 0.0, 255.0)));
      const double dv = std::clamp(depth[s] / 65535.0 / std::max(ad, 1e-9), 0.0, 1.0);
      nb[d + 3] = std::uint8_t(std::lround(dv * 255.0));
    }
  }
}

void read_layered_row(const BakeTarget& t, int band_y, bool blended, RowPixels& px, BakedMaps& out) {
  const std::size_t n = std::size_t(t.width) * std::size_t(t.height);
  if (px.packed.size() < n * 4) {
    px.packed.resize(n * 4);
    px.color16.resize(n * 4);
    px.normal.resize(n * 4);
    px.depth.resize(n * 4);
  }
  glBindFramebuffer(GL_READ_FRAMEBUFFER, t.draw_fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_COLOR_ATTACHMENT3);
  glReadPixels(0, 0, t.width, t.height, GL_RGBA_INTEGER, GL_UNSIGNED_SHORT, px.packed.data());
  if (blended) {  // else the blended layers stay as resize() made them: 0
    std::uint16_t* layers[3] = {px.color16.data(), px.normal.data(), px.depth.data()};
    for (int a = 0; a < 3; ++a) {
      glReadBuffer(GL_COLOR_ATTACHMENT0 + GLenum(a));
      glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_SHORT, layers[a]);
    }
  }
  auto& cb = out.color.bytes();
  auto& nb = out.normal_depth.bytes();
  const std::size_t stride = std::size_t(out.color.width()) * 4;
  for (int y = 0; y < t.height; ++y) {
    const std::size_t src_row = std::size_t(t.height - 1 - y) * std::size_t(t.width) * 4;  // bottom up
    const std::size_t dst_row = std::size_t(band_y + y) * stride;
    for (int x = 0; x < t.width; ++x) {
      const std::size_t s = src_row + std::size_t(x) * 4, d = dst_row + std::size_t(x) * 4;
      composite_bake_texel(&px.packed[s], &px.color16[s], &px.normal[s], &px.depth[s], &cb[d], &nb[d]);
    }
  }
}

}  // namespace sylva::render::detail
