// The renderer: draws a Scene from a Camera into an 8-bit RGBA image.
//
// Renderer is an interface so that code built on it (the `sylva render` command, the verify
// stage, the impostor baker) can be tested with a fake; Renderer::create_headless() gives the
// real one: OpenGL 3.3 core through EGL with no window and no GPU needed (Mesa llvmpipe).
//
// Contract of the real renderer (docs/renderer.md has the details):
//  - Deterministic: the same scene, camera and options give the same pixels on the same machine
//    (and, with the default software device, on every machine with the same Mesa version).
//  - Passes: opaque and alpha-masked primitives first (depth write on); then every BLEND
//    primitive (semi-transparent lines in particular), draws sorted far to near by the distance
//    of their bounding-box centre, and the elements inside each draw sorted far to near, with
//    depth test on and depth write off (Zhang et al. 2017, §6.1).
//  - Lighting: colour = base * (ambient + light_color * max(0, n.l)) in linear space, then
//    encoded to sRGB. base = baseColorFactor * COLOR_0 * texture (sRGB-decoded).
//    glTF's two-sided rule: the back face (by winding; clockwise under a mirroring matrix) of a
//    double-sided triangle is lit with the reversed normal, nothing is inferred from the eye;
//    triangles without normals use flat face normals; LINES (as in three.js), points without
//    normals and KHR_materials_unlit materials are unlit; points with normals use them as given.
//  - Thread safety: render calls are serialised by an internal mutex; the GL context is made
//    current on the calling thread for the duration of a call and released afterwards, so one
//    Renderer may be shared by threads (they take turns).
#pragma once

#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/image/image.h"
#include "libs/render/camera.h"
#include "libs/render/scene.h"

namespace sylva::render {

// Rendering failed (invalid options, an internal GL error). what() is one line.
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// No usable EGL / OpenGL 3.3 core on this machine. what() is one line that starts with
// "headless OpenGL is not available: " and says what each attempt reported.
class RenderUnavailableError : public RenderError {
 public:
  using RenderError::RenderError;
};

struct Lighting {
  Vec3 ambient = Vec3::Constant(0.35f);                           // linear RGB
  Vec3 light_color = Vec3::Constant(0.75f);                       // linear RGB of the directional light
  Vec3 direction_to_light = Vec3(0.3f, 1.0f, 0.5f).normalized();  // world space, need not be unit
};

struct RenderOptions {
  int width = 1024;  // pixels, 1..GL_MAX_RENDERBUFFER_SIZE
  int height = 1024;
  int msaa = 4;  // samples per pixel; 1 = no multisampling; at most GL_MAX_SAMPLES (4 on llvmpipe)
  // k in 1..4: draw a k·width x k·height image (with `msaa` samples per pixel of it) and average
  // each k x k block into one pixel; line widths and point sizes stay in output pixels. On
  // llvmpipe msaa 1 with k = 2 costs about a third of msaa 4 for dense foliage (docs/renderer.md).
  int supersample = 1;
  image::Rgba8 background{191, 204, 217, 255};  // sRGB-encoded; alpha 0 gives a transparent image
  Lighting lighting;
  float default_point_size_px = 2.f;  // POINTS without _SIZE
  float min_point_size_px = 1.f;      // sized points are never drawn smaller than this
  float line_width_px = 1.f;          // width of LINES in pixels
  // Hybrid antialiasing only (supersample k, msaa k^2): impostor fragments all of whose samples
  // the meshes hide are discarded before the impostor shader's march (its SYLVA_SCENE_DEPTH,
  // docs/renderer.md "Impostor march"); llvmpipe would march them and then drop every sample.
  // The pixels are the same either way; false is for comparisons (tests, bench_forest_view).
  bool impostor_hidden_discard = true;
};

class Renderer {
 public:
  virtual ~Renderer() = default;

  // The real renderer. Prefers Mesa's software device (EGL_EXT_platform_device with
  // EGL_MESA_device_software: llvmpipe, identical results on every machine), then the surfaceless
  // platform (EGL_MESA_platform_surfaceless), then any EGL device. Throws RenderUnavailableError
  // when none gives an OpenGL 3.3 core context.
  static std::unique_ptr<Renderer> create_headless();

  // Renders every camera with one upload of the scene. Images are width x height, top row first.
  // What stays uploaded between calls: the buffers of meshes naming shared geometry
  // (Mesh::shared_geometry) while the name lives, impostor maps while their atlas lives, and the
  // target while the size and sampling stay the same; the pixels are those of a fresh upload.
  // Throws RenderError for invalid options (size, msaa above what the device supports).
  virtual std::vector<image::Image> render_views(const Scene& scene, std::span<const Camera> cameras,
                                                 const RenderOptions& options) = 0;

  // Uploads what render_views keeps between calls for `scene` and `options` (the target, the
  // buffers of meshes naming shared geometry, the impostor maps) without drawing, so that the
  // views drawn next spend their time drawing: a forest's loading step (ForestView::prepare).
  // Meshes' instances and textures are not looked at (textures are uploaded per call). Throws
  // as render_views does. The default does nothing (fakes).
  virtual void prepare(const Scene& scene, const RenderOptions& options) {
    (void)scene;
    (void)options;
  }
  // One view.
  image::Image render(const Scene& scene, const Camera& camera, const RenderOptions& options) {
    return std::move(render_views(scene, std::span<const Camera>(&camera, 1), options).front());
  }

  // The device, for reports: e.g. "llvmpipe (LLVM 15.0.6, 256 bits); OpenGL 4.5 (Core Profile) Mesa 22.3.6".
  virtual std::string device_description() const = 0;

  // Meshes whose buffers are kept uploaded after the last call: the Mesh::shared_geometry names
  // drawn so far that still live (a name found dead at a call's start is dropped then). For tests.
  virtual std::size_t kept_geometry() const { return 0; }
  // Impostor atlases whose maps are kept uploaded after the last call (they are dropped at the
  // first call after their atlas is gone). For tests.
  virtual std::size_t kept_impostor_atlases() const { return 0; }
};

// RenderOptions for a camera set: `base` with the set's width, height, msaa and supersample.
RenderOptions options_for(const CameraSet& set, RenderOptions base = {});

struct RenderedView {
  Camera camera;  // camera.name is the view name
  image::Image image;
};

// Resolves every view of `set` against the scene's bounds and renders them (one upload).
std::vector<RenderedView> render_camera_set(Renderer& renderer, const Scene& scene, const CameraSet& set,
                                            const RenderOptions& base = {});

}  // namespace sylva::render
