// Private: the OpenGL plumbing every drawing path of libs/render shares (the scene renderer, the
// impostor baker and drawers): ownership of GL names, a scoped current context, the device's
// limits, error checks, shader programs, texture upload and colour read-back.
//
// Every function expects the context to be current on the calling thread.
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdint>
#include <string>
#include <vector>

#include "libs/image/image.h"
#include "libs/render/gl_context.h"
#include "libs/render/scene.h"

namespace sylva::render::detail {

// Every GL name created during one call, deleted when the call ends (the context is still
// current then).
struct GlObjects {
  std::vector<GLuint> buffers, textures, vertex_arrays, framebuffers, renderbuffers;
  GlObjects() = default;
  GlObjects(const GlObjects&) = delete;
  GlObjects& operator=(const GlObjects&) = delete;
  ~GlObjects();
  GLuint buffer();
  GLuint texture();
  GLuint vertex_array();
  GLuint framebuffer();
  GLuint renderbuffer();
};

// Makes the context current for a scope and releases it afterwards.
class CurrentContext {
 public:
  explicit CurrentContext(GlContext& ctx) : ctx_(ctx) { ctx_.make_current(); }
  ~CurrentContext() { ctx_.release(); }
  CurrentContext(const CurrentContext&) = delete;
  CurrentContext& operator=(const CurrentContext&) = delete;

 private:
  GlContext& ctx_;
};

// What the device allows (queried once per context).
struct DeviceLimits {
  GLint max_samples = 1;                   // GL_MAX_SAMPLES
  GLint max_renderbuffer_size = 4096;      // GL_MAX_RENDERBUFFER_SIZE: pixels per side of a target
  GLint max_texture_size = 4096;           // GL_MAX_TEXTURE_SIZE
  float line_width_range[2] = {1.f, 1.f};  // GL_ALIASED_LINE_WIDTH_RANGE, pixels
};
DeviceLimits query_device_limits();

// Throws RenderError("OpenGL error during <where>: GL_...") if glGetError() reports one.
void check_gl(const char* where);

// Throws RenderError unless a w x h target with `msaa` samples fits the device: "<what> size WxH
// is outside 1..N" (N: the largest renderbuffer side) or "msaa M is not supported (this device
// allows 1..S)".
void check_target_size(const char* what, int w, int h, int msaa, const DeviceLimits& limits);

// A w x h renderbuffer of `format` (multisampled when samples > 1) attached to `fbo` at
// `attachment`; leaves `fbo` bound to GL_FRAMEBUFFER.
void attach_renderbuffer(GlObjects& gl, GLuint fbo, GLenum attachment, GLenum format, int samples, int w,
                         int h);

// Clears the bound framebuffer's colour to `background` (8-bit sRGB-encoded; alpha 0 clears to
// transparent black) and its depth to 1, with depth writes on and the depth test GL_LESS.
void clear_to_background(image::Rgba8 background);

// A linked program from vertex and fragment sources. A compile or link failure throws
// RenderUnavailableError ("headless OpenGL is not available: shader ... failed: <log>"): the
// device cannot run the shaders every render needs. `name` goes into the message.
GLuint link_program(const char* vertex_source, const char* fragment_source, const std::string& name);

// A buffer object holding `data` (GL_STATIC_DRAW), bound to `target`.
template <typename T>
GLuint upload_array(GlObjects& gl, GLenum target, const std::vector<T>& data) {
  const GLuint b = gl.buffer();
  glBindBuffer(target, b);
  glBufferData(target, GLsizeiptr(data.size() * sizeof(T)), data.data(), GL_STATIC_DRAW);
  return b;
}

GLint gl_wrap(Wrap w);

// The GL primitive mode of a topology (GL_LINES, GL_POINTS, else GL_TRIANGLES).
GLenum gl_mode(Topology t);

// Gives the bound GL_TEXTURE_2D, which must have no storage yet, immutable storage for levels
// 0..mip_levels (glTexStorage2D; at most down to 1 x 1) of a width x height RGBA8 image
// (GL_SRGB8_ALPHA8 when `srgb`), fills level 0 from `rgba` (rows top first, 4 bytes a texel, no
// padding), generates the others (glGenerateMipmap) and samples them trilinearly, clamped to the
// edge (bilinear when mip_levels is 0). An impostor map: 64 or 151 MB at level 0
// (docs/performance.md "Forest", "Levers kept").
void upload_mipmapped_rgba8(const std::uint8_t* rgba, int width, int height, bool srgb, int mip_levels);

// Uploads an 8-bit sRGB-encoded RGBA texture (sampling returns linear values) with its sampler
// state; mipmaps are generated when the texture asks for them. Throws RenderError for
// inconsistent sizes.
GLuint upload_texture(GlObjects& gl, const Texture& t);

// Colour attachment 0 of `fbo` (single-sampled RGBA8, at least width x height) as an Image, top
// row first. With `unpremultiply` (drawn over a transparent background, so the framebuffer holds
// premultiplied colour) each colour is divided by its alpha, so the image holds straight alpha.
image::Image read_rgba8(GLuint fbo, int width, int height, bool unpremultiply);

}  // namespace sylva::render::detail
