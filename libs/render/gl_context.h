// Private: the OpenGL context the renderer draws with, behind a narrow interface.
//
// GL entry points are called directly (GL_GLEXT_PROTOTYPES against GLVND's libOpenGL, which
// dispatches to whichever vendor owns the current EGL context), so no loader such as glad or
// GLEW is involved; the context only has to be current on the calling thread.
#pragma once

#include <memory>
#include <string>

namespace sylva::render::detail {

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual void make_current() = 0;              // on the calling thread; throws RenderError on failure
  virtual void release() = 0;                   // detaches from the calling thread
  virtual std::string description() const = 0;  // "GL_RENDERER; GL_VERSION"
};

// An OpenGL 3.3 core context with no window surface. Tries, in order: Mesa's software EGL
// device, the surfaceless platform, every other EGL device. Throws RenderUnavailableError,
// whose message says what each attempt reported.
std::unique_ptr<GlContext> create_egl_context();

}  // namespace sylva::render::detail
