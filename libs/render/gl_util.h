// Private: the OpenGL plumbing every drawing path of libs/render shares (the scene renderer in
// gl_renderer.cpp, the impostor baker and drawer in impostor_renderer.cpp): ownership of GL
// names, a scoped current context, error checks, shader programs and texture upload.
//
// Every function expects the context to be current on the calling thread.
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdint>
#include <string>
#include <vector>

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

// Throws RenderError("OpenGL error during <where>: GL_...") if glGetError() reports one.
void check_gl(const char* where);

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

}  // namespace sylva::render::detail
