// The GL plumbing shared by the scene renderer and the impostor renderer (gl_util.h).
#include "libs/render/gl_util.h"

#include <algorithm>
#include <cstring>

#include "libs/render/renderer.h"

namespace sylva::render::detail {

GlObjects::~GlObjects() {
  if (!buffers.empty()) glDeleteBuffers(GLsizei(buffers.size()), buffers.data());
  if (!textures.empty()) glDeleteTextures(GLsizei(textures.size()), textures.data());
  if (!vertex_arrays.empty()) glDeleteVertexArrays(GLsizei(vertex_arrays.size()), vertex_arrays.data());
  if (!framebuffers.empty()) glDeleteFramebuffers(GLsizei(framebuffers.size()), framebuffers.data());
  if (!renderbuffers.empty()) glDeleteRenderbuffers(GLsizei(renderbuffers.size()), renderbuffers.data());
}

namespace {

// One new name from `gen` (a glGen* function), kept in `owned` to be deleted with the others.
template <typename Gen>
GLuint generate(Gen gen, std::vector<GLuint>& owned) {
  GLuint name = 0;
  gen(1, &name);
  owned.push_back(name);
  return name;
}

}  // namespace

GLuint GlObjects::buffer() { return generate(glGenBuffers, buffers); }
GLuint GlObjects::texture() { return generate(glGenTextures, textures); }
GLuint GlObjects::vertex_array() { return generate(glGenVertexArrays, vertex_arrays); }
GLuint GlObjects::framebuffer() { return generate(glGenFramebuffers, framebuffers); }
GLuint GlObjects::renderbuffer() { return generate(glGenRenderbuffers, renderbuffers); }

namespace {

std::string gl_error_name(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    default:
      return "GL error " + std::to_string(e);
  }
}

GLuint compile(GLenum type, const char* source, const std::string& name) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw RenderUnavailableError("headless OpenGL is not available: shader compilation failed (" + name +
                                 "): " + log);
  }
  return s;
}

}  // namespace

DeviceLimits query_device_limits() {
  DeviceLimits d;
  glGetIntegerv(GL_MAX_SAMPLES, &d.max_samples);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &d.max_renderbuffer_size);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &d.max_texture_size);
  glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, d.line_width_range);
  return d;
}

void check_gl(const char* where) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR)
    throw RenderError(std::string("OpenGL error during ") + where + ": " + gl_error_name(e));
}

void check_target_size(const char* what, int w, int h, int msaa, const DeviceLimits& limits) {
  const GLint max_size = limits.max_renderbuffer_size;
  if (w < 1 || h < 1 || w > max_size || h > max_size)
    throw RenderError(std::string(what) + " size " + std::to_string(w) + "x" + std::to_string(h) +
                      " is outside 1.." + std::to_string(max_size));
  if (msaa < 1 || msaa > limits.max_samples)
    throw RenderError("msaa " + std::to_string(msaa) + " is not supported (this device allows 1.." +
                      std::to_string(limits.max_samples) + ")");
}

void attach_renderbuffer(GlObjects& gl, GLuint fbo, GLenum attachment, GLenum format, int samples, int w,
                         int h) {
  const GLuint rb = gl.renderbuffer();
  glBindRenderbuffer(GL_RENDERBUFFER, rb);
  if (samples > 1) {
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, w, h);
  } else {
    glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, rb);
}

void clear_to_background(image::Rgba8 background) {
  const bool transparent = background.a == 0;
  glClearColor(transparent ? 0.f : background.r / 255.f, transparent ? 0.f : background.g / 255.f,
               transparent ? 0.f : background.b / 255.f, background.a / 255.f);
  glClearDepth(1.0);
  glDepthMask(GL_TRUE);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
}

GLuint link_program(const char* vertex_source, const char* fragment_source, const std::string& name) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex_source, name);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment_source, name);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    glDeleteProgram(program);
    throw RenderUnavailableError("headless OpenGL is not available: shader linking failed (" + name +
                                 "): " + log);
  }
  return program;
}

GLenum gl_mode(Topology t) {
  switch (t) {
    case Topology::kLines:
      return GL_LINES;
    case Topology::kPoints:
      return GL_POINTS;
    default:
      return GL_TRIANGLES;
  }
}

GLint gl_wrap(Wrap w) {
  switch (w) {
    case Wrap::kClampToEdge:
      return GL_CLAMP_TO_EDGE;
    case Wrap::kMirroredRepeat:
      return GL_MIRRORED_REPEAT;
    default:
      return GL_REPEAT;
  }
}

void upload_mipmapped_rgba8(const std::uint8_t* rgba, int width, int height, bool srgb, int mip_levels) {
  // Storage for every level at once: with glTexImage2D's level 0 alone, Mesa allocates the other
  // levels when they are generated and moves level 0 into the new storage (forest_celba's walk
  // took 1.4-3.2 s to upload its impostor maps that way, 1.2-1.5 s this way). GL_TEXTURE_MAX_LEVEL
  // beyond the 1 x 1 level meant the whole chain; immutable storage cannot hold more than that.
  int full_chain = 0;
  while ((std::max(width, height) >> (full_chain + 1)) > 0) ++full_chain;
  const int levels = std::clamp(mip_levels, 0, full_chain);
  glTexStorage2D(GL_TEXTURE_2D, levels + 1, srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, width, height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, levels > 0 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  if (levels > 0) glGenerateMipmap(GL_TEXTURE_2D);
}

GLuint upload_texture(GlObjects& gl, const Texture& t) {
  if (t.width <= 0 || t.height <= 0 || t.rgba.size() != std::size_t(t.width) * std::size_t(t.height) * 4)
    throw RenderError("texture '" + t.name + "' has inconsistent size and pixel data");
  const GLuint id = gl.texture();
  glBindTexture(GL_TEXTURE_2D, id);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  // sRGB storage: sampling returns linear values, as the lighting expects.
  glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, t.width, t.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
               t.rgba.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, gl_wrap(t.wrap_s));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, gl_wrap(t.wrap_t));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER,
                  t.mag_filter == Filter::kNearest ? GL_NEAREST : GL_LINEAR);
  GLint min = t.min_filter == Filter::kNearest ? GL_NEAREST : GL_LINEAR;
  if (t.mipmaps) {
    min = t.min_filter == Filter::kNearest ? GL_NEAREST_MIPMAP_LINEAR : GL_LINEAR_MIPMAP_LINEAR;
    glGenerateMipmap(GL_TEXTURE_2D);
  }
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, min);
  return id;
}

image::Image read_rgba8(GLuint fbo, int width, int height, bool unpremultiply) {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  std::vector<std::uint8_t> raw(std::size_t(width) * std::size_t(height) * 4);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
  image::Image img(width, height);
  const std::size_t row = std::size_t(width) * 4;
  for (int y = 0; y < height; ++y)  // GL's first row is the bottom one
    std::memcpy(&img.bytes()[std::size_t(y) * row], &raw[std::size_t(height - 1 - y) * row], row);
  if (unpremultiply) {
    auto& px = img.bytes();
    for (std::size_t i = 0; i < px.size(); i += 4) {
      const int a = px[i + 3];
      if (a == 0 || a == 255) continue;
      for (int c = 0; c < 3; ++c)
        px[i + std::size_t(c)] = std::uint8_t(std::min(255, (px[i + std::size_t(c)] * 255 + a / 2) / a));
    }
  }
  return img;
}

}  // namespace sylva::render::detail
