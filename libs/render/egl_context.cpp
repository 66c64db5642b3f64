// EGL without a window: an OpenGL (desktop, 3.3 core) context made current with no surface
// (EGL_KHR_surfaceless_context), on a display from EGL_EXT_platform_device or
// EGL_MESA_platform_surfaceless. Rendering goes to framebuffer objects only.
//
// An EGLDisplay belongs to the process, not to the caller: eglGetPlatformDisplayEXT hands every
// caller the same display for the same device, eglInitialize of an initialised display does
// nothing, and eglTerminate marks every context of the display for deletion, other renderers'
// included; a context that is not current at that moment is gone at once (EGL 1.5 §3.2, §3.4).
// Pipeline nodes create and destroy renderers on
// several threads at once, so the displays are counted (DisplayUse below): the first user
// initialises a display, the last one terminates it, under one mutex.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "libs/render/gl_context.h"
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <vector>

#include "libs/render/renderer.h"

namespace sylva::render::detail {
namespace {

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  }
  return false;
}

std::string egl_error_name(EGLint e) {
  switch (e) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    default: {
      char buf[32];
      std::snprintf(buf, sizeof buf, "EGL error 0x%x", unsigned(e));
      return buf;
    }
  }
}

// How many contexts of this file use each display it initialised.
class DisplayUse {
 public:
  // eglInitialize for the first user; false (and no use counted) when that fails.
  bool acquire(EGLDisplay display) {
    const std::lock_guard lock(mutex_);
    int& users = users_[display];
    if (users == 0) {
      EGLint major = 0, minor = 0;
      if (!eglInitialize(display, &major, &minor)) {
        users_.erase(display);
        return false;
      }
    }
    ++users;
    return true;
  }
  // eglTerminate when the last user goes.
  void release(EGLDisplay display) {
    const std::lock_guard lock(mutex_);
    const auto it = users_.find(display);
    if (it == users_.end() || --it->second > 0) return;
    users_.erase(it);
    eglTerminate(display);
  }

 private:
  std::mutex mutex_;
  std::map<EGLDisplay, int> users_;
};

// Never destroyed: a renderer may outlive static destruction (a global in a test or a tool).
DisplayUse& display_use() {
  static DisplayUse* use = new DisplayUse;
  return *use;
}

class EglContext final : public GlContext {
 public:
  EglContext(EGLDisplay display, EGLContext context) : display_(display), context_(context) {}
  ~EglContext() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    display_use().release(display_);
  }
  void make_current() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      throw RenderError("cannot make the OpenGL context current: " + egl_error_name(eglGetError()));
  }
  void release() override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }
  std::string description() const override { return description_; }
  void set_description(std::string d) { description_ = std::move(d); }

 private:
  EGLDisplay display_;
  EGLContext context_;
  std::string description_;
};

// Initialises `display` and creates a current 3.3 core context, or returns the reason it failed.
std::unique_ptr<EglContext> try_display(EGLDisplay display, std::string& why) {
  if (display == EGL_NO_DISPLAY) {
    why = "no display (" + egl_error_name(eglGetError()) + ")";
    return nullptr;
  }
  if (!display_use().acquire(display)) {
    why = "eglInitialize failed (" + egl_error_name(eglGetError()) + ")";
    return nullptr;
  }
  const char* exts = eglQueryString(display, EGL_EXTENSIONS);
  if (!has_extension(exts, "EGL_KHR_surfaceless_context")) {
    why = "EGL_KHR_surfaceless_context is not supported";
    display_use().release(display);
    return nullptr;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    why = "desktop OpenGL is not supported (" + egl_error_name(eglGetError()) + ")";
    display_use().release(display);
    return nullptr;
  }
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_extension(exts, "EGL_KHR_no_config_context") &&
      !has_extension(exts, "EGL_MESA_configless_context")) {
    const EGLint attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(display, attribs, &config, 1, &n) || n < 1) {
      why = "no EGL config supports desktop OpenGL";
      display_use().release(display);
      return nullptr;
    }
  }
  const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                3,
                                EGL_CONTEXT_MINOR_VERSION,
                                3,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                EGL_NONE};
  EGLContext ctx = eglCreateContext(display, config, EGL_NO_CONTEXT, ctx_attribs);
  if (ctx == EGL_NO_CONTEXT) {
    why = "cannot create an OpenGL 3.3 core context (" + egl_error_name(eglGetError()) + ")";
    display_use().release(display);
    return nullptr;
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
    why = "cannot make the context current (" + egl_error_name(eglGetError()) + ")";
    eglDestroyContext(display, ctx);
    display_use().release(display);
    return nullptr;
  }
  auto out = std::make_unique<EglContext>(display, ctx);
  const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  out->set_description(std::string(renderer ? renderer : "?") + "; OpenGL " + (version ? version : "?"));
  out->release();
  return out;
}

}  // namespace

std::unique_ptr<GlContext> create_egl_context() {
  std::vector<std::string> attempts;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!client) {
    throw RenderUnavailableError(
        "headless OpenGL is not available: EGL has no client extensions (no EGL vendor library "
        "found; install Mesa's EGL, Debian package libegl-mesa0)");
  }
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_device_string =
      reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  const bool platform_base = has_extension(client, "EGL_EXT_platform_base") && get_platform_display;

  std::vector<EGLDeviceEXT> devices;
  if (platform_base && has_extension(client, "EGL_EXT_platform_device") && query_devices) {
    EGLint n = 0;
    if (query_devices(0, nullptr, &n) && n > 0) {
      devices.resize(std::size_t(n));
      query_devices(n, devices.data(), &n);
      devices.resize(std::size_t(std::max(n, 0)));
    }
  }
  auto is_software = [&](EGLDeviceEXT d) {
    return query_device_string &&
           has_extension(query_device_string(d, EGL_EXTENSIONS), "EGL_MESA_device_software");
  };

  std::string why;
  // 1. Mesa's software device: llvmpipe on every machine, so references match everywhere.
  for (EGLDeviceEXT d : devices) {
    if (!is_software(d)) continue;
    if (auto ctx = try_display(get_platform_display(EGL_PLATFORM_DEVICE_EXT, d, nullptr), why)) return ctx;
    attempts.push_back("software device: " + why);
  }
  // 2. The surfaceless platform.
  if (platform_base && has_extension(client, "EGL_MESA_platform_surfaceless")) {
    if (auto ctx = try_display(
            get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr), why))
      return ctx;
    attempts.push_back("surfaceless platform: " + why);
  } else {
    attempts.push_back("surfaceless platform: EGL_MESA_platform_surfaceless is not supported");
  }
  // 3. Any other device.
  for (EGLDeviceEXT d : devices) {
    if (is_software(d)) continue;
    if (auto ctx = try_display(get_platform_display(EGL_PLATFORM_DEVICE_EXT, d, nullptr), why)) return ctx;
    attempts.push_back("EGL device: " + why);
  }
  if (devices.empty()) attempts.push_back("no EGL devices");
  std::string msg = "headless OpenGL is not available: ";
  for (std::size_t i = 0; i < attempts.size(); ++i) msg += (i ? "; " : "") + attempts[i];
  throw RenderUnavailableError(msg);
}

}  // namespace sylva::render::detail
