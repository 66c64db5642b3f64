// The scene renderer's targets and the passes between them (render_target.h).
#include "libs/render/render_target.h"

#include <algorithm>
#include <string>

#include "libs/render/shaders.h"

namespace sylva::render::detail {
namespace {

// A w x h texture read with texelFetch (one level, nearest), attached to `fbo`.
GLuint attach_texture(GlObjects& gl, GLuint fbo, GLenum attachment, GLenum internal, GLenum format,
                      GLenum type, int w, int h) {
  const GLuint tex = gl.texture();
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal), w, h, 0, format, type, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_2D, tex, 0);
  return tex;
}

void complete(const std::string& what) {
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw RenderError("cannot create " + what);
}

// Hybrid: the multisampled target of the output size, which sample stands for which sub-pixel,
// and the farthest-depth target.
void make_hybrid_targets(GlObjects& gl, const RenderOptions& o, RenderTarget& t) {
  const int k = o.supersample;
  t.samples_fbo = gl.framebuffer();
  t.samples_texture = gl.texture();
  glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, t.samples_texture);
  glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, o.msaa, GL_RGBA8, o.width, o.height, GL_TRUE);
  glBindFramebuffer(GL_FRAMEBUFFER, t.samples_fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE, t.samples_texture,
                         0);
  attach_renderbuffer(gl, t.samples_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, o.msaa, o.width,
                      o.height);
  complete("the multisampled framebuffer");
  // Each sample stands for the sub-pixel its position falls in (the device's pattern has
  // one sample per k x k cell, as the standard 4-sample pattern does for k = 2); else by index.
  t.sample_of.assign(std::size_t(k * k), -1);
  bool bijective = true;
  for (int s = 0; s < o.msaa; ++s) {
    GLfloat pos[2] = {0.5f, 0.5f};
    glGetMultisamplefv(GL_SAMPLE_POSITION, GLuint(s), pos);
    const int sx = std::clamp(int(pos[0] * float(k)), 0, k - 1),
              sy = std::clamp(int(pos[1] * float(k)), 0, k - 1);
    int& slot = t.sample_of[std::size_t(sx + k * sy)];
    bijective = bijective && slot < 0;
    slot = s;
  }
  if (!bijective)
    for (int s = 0; s < o.msaa; ++s) t.sample_of[std::size_t(s)] = s;
  t.farthest_fbo = gl.framebuffer();
  t.farthest_texture =
      attach_texture(gl, t.farthest_fbo, GL_COLOR_ATTACHMENT0, GL_R32F, GL_RED, GL_FLOAT, o.width, o.height);
  complete("the farthest-depth framebuffer");
}

RenderTarget make_target(GlObjects& gl, const RenderOptions& o) {
  RenderTarget t;
  const int k = o.supersample;
  t.width = o.width * k;
  t.height = o.height * k;
  t.draw_fbo = gl.framebuffer();
  if (k == 1) {
    attach_renderbuffer(gl, t.draw_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, o.msaa, t.width, t.height);
    attach_renderbuffer(gl, t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, o.msaa, t.width,
                        t.height);
    complete("a " + std::to_string(t.width) + "x" + std::to_string(t.height) + " framebuffer");
    t.resolve_fbo = t.output_fbo = t.draw_fbo;
    if (o.msaa > 1) {
      t.resolve_fbo = t.output_fbo = gl.framebuffer();
      attach_renderbuffer(gl, t.resolve_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, 1, t.width, t.height);
      complete("the resolve framebuffer");
    }
    return t;
  }
  t.color_texture = attach_texture(gl, t.draw_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE,
                                   t.width, t.height);
  if (hybrid(o)) {
    t.depth_texture = attach_texture(gl, t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F,
                                     GL_DEPTH_COMPONENT, GL_FLOAT, t.width, t.height);
  } else {
    attach_renderbuffer(gl, t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, 1, t.width, t.height);
  }
  complete("a " + std::to_string(t.width) + "x" + std::to_string(t.height) + " framebuffer");
  t.resolve_fbo = t.draw_fbo;
  t.output_fbo = gl.framebuffer();
  attach_renderbuffer(gl, t.output_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, 1, o.width, o.height);
  complete("the downsampling framebuffer");
  t.empty_vao = gl.vertex_array();
  if (hybrid(o)) make_hybrid_targets(gl, o, t);
  return t;
}

}  // namespace

const RenderTarget& KeptTarget::for_options(const RenderOptions& o) {
  if (!gl_ || width_ != o.width || height_ != o.height || msaa_ != o.msaa || supersample_ != o.supersample) {
    gl_.reset();
    auto gl = std::make_unique<GlObjects>();
    target_ = make_target(*gl, o);
    gl_ = std::move(gl);
    width_ = o.width;
    height_ = o.height;
    msaa_ = o.msaa;
    supersample_ = o.supersample;
  }
  return target_;
}

void TargetPasses::link() {
  downsample_ = link_program(kFullscreenVert, with_prelude(kBlockReduceFrag, kBlockMeanGlsl, "block").c_str(),
                             "downsample");
  to_samples_ = link_program(kFullscreenVert, kToSamplesFrag, "to samples");
  farthest_depth_ = link_program(
      kFullscreenVert, with_prelude(kBlockReduceFrag, kBlockMaxGlsl, "block").c_str(), "farthest depth");
  from_samples_ = link_program(kFullscreenVert, kFromSamplesFrag, "from samples");
}

void TargetPasses::destroy() {
  glDeleteProgram(downsample_);
  glDeleteProgram(to_samples_);
  glDeleteProgram(farthest_depth_);
  glDeleteProgram(from_samples_);
}

// One full-screen triangle at the output size into `fbo` with `program` (block_reduce.frag)
// reading `texture`: the downsample and the farthest-depth passes. Leaves depth test, blending,
// culling and multisampling off.
void TargetPasses::output_pass(const RenderTarget& t, const RenderOptions& o, GLuint fbo, GLuint program,
                               GLuint texture) const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, o.width, o.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_MULTISAMPLE);
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "u_source"), 0);
  glUniform1i(glGetUniformLocation(program, "u_k"), o.supersample);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, texture);
  glBindVertexArray(t.empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

void TargetPasses::farthest_depth(const RenderTarget& t, const RenderOptions& o) const {
  output_pass(t, o, t.farthest_fbo, farthest_depth_, t.depth_texture);
}

void TargetPasses::to_samples(const RenderTarget& t, const RenderOptions& o) const {
  const int k = o.supersample;
  glBindFramebuffer(GL_FRAMEBUFFER, t.samples_fbo);
  glViewport(0, 0, o.width, o.height);
  glEnable(GL_MULTISAMPLE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_ALWAYS);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glUseProgram(to_samples_);
  glUniform1i(glGetUniformLocation(to_samples_, "u_color"), 0);
  glUniform1i(glGetUniformLocation(to_samples_, "u_depth"), 1);
  glUniform1i(glGetUniformLocation(to_samples_, "u_k"), k);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, t.color_texture);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, t.depth_texture);
  glActiveTexture(GL_TEXTURE0);
  glBindVertexArray(t.empty_vao);
  glEnable(GL_SAMPLE_MASK);
  const GLint sub = glGetUniformLocation(to_samples_, "u_sub");
  for (int i = 0; i < k * k; ++i) {
    glSampleMaski(0, 1u << unsigned(t.sample_of[std::size_t(i)]));
    glUniform2i(sub, i % k, i / k);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glDisable(GL_SAMPLE_MASK);
  glBindVertexArray(0);
  glDepthFunc(GL_LESS);
}

void TargetPasses::from_samples(const RenderTarget& t, const RenderOptions& o) const {
  const int k = o.supersample;
  glBindFramebuffer(GL_FRAMEBUFFER, t.draw_fbo);
  glViewport(0, 0, t.width, t.height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glUseProgram(from_samples_);
  glUniform1i(glGetUniformLocation(from_samples_, "u_samples"), 0);
  glUniform1i(glGetUniformLocation(from_samples_, "u_k"), k);
  glUniform1iv(glGetUniformLocation(from_samples_, "u_sample_of"), GLsizei(t.sample_of.size()),
               t.sample_of.data());
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, t.samples_texture);
  glBindVertexArray(t.empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
}

image::Image TargetPasses::read_back(const RenderTarget& t, const RenderOptions& o) const {
  if (t.resolve_fbo != t.draw_fbo) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.draw_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolve_fbo);
    glBlitFramebuffer(0, 0, t.width, t.height, 0, 0, t.width, t.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  }
  if (t.output_fbo != t.resolve_fbo) {
    output_pass(t, o, t.output_fbo, downsample_, t.color_texture);
    glEnable(GL_DEPTH_TEST);
  }
  // Over a transparent background the framebuffer holds premultiplied colour.
  return read_rgba8(t.output_fbo, o.width, o.height, o.background.a == 0);
}

}  // namespace sylva::render::detail
