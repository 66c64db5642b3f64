// Baking impostor atlases and drawing (hemi-)octahedral impostors, on the same headless OpenGL
// (EGL, Mesa llvmpipe) as the scene renderer (renderer.h).
//
// Bake: a Scene is drawn into an atlas once per BakeView, an orthographic view of a rectangle in
// object space, into that view's pixel rectangle of the atlas. Every view of one atlas row is one
// instanced draw per primitive (the instance selects the view's transform from a uniform array;
// every view frames the whole source, so nothing reaches a neighbouring rectangle), so 256
// frames cost 16 draws per primitive, not 256. Textures are sampled from the mip level nearest
// the texel's footprint (bilinear within it, not trilinear: docs/stages/impostor.md). Three maps come out
// (docs/stages/impostor.md, "Maps"):
//   - colour: the sRGB-encoded base colour (baseColorFactor * COLOR_0 * texture, unlit) with
//     straight alpha = the coverage of the texel (MSAA samples covered; BLEND primitives add
//     their alpha over what lies behind them, as the scene renderer composites them);
//   - normal: the shading normal in object space by the scene renderer's rules (glTF: the back
//     face of a double-sided triangle, by winding, has the reversed normal; single-sided back
//     faces are culled); lines' normals are turned toward the view (twigs, lit; the scene
//     renderer draws LINES unlit as three.js does),
//     encoded n * 0.5 + 0.5, averaged over the covered samples and renormalised;
//   - depth: h / R * 0.5 + 0.5, h = (X - centre) . dir, averaged over the covered samples.
//   Texels nothing covers are (0,0,0,0) in every map (dilation is the caller's business).
//   Materials are read as the scene renderer reads them (alpha modes, cutoff, textures).
//
// Draw: render_octahedral() draws impostor instances with the reference shader
// (libs/render/shaders/octahedral_impostor.{vert,frag}, shipped for engines): one camera-facing
// quad per instance, the maps premultiplied by coverage before upload (the shader's contract),
// three frames blended by the view direction, each reprojected with its depth (parallax), lit
// with RenderOptions::lighting like the scene renderer, blended over the background with alpha =
// coverage. Same determinism and thread-safety contract as Renderer.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "libs/image/image.h"
#include "libs/render/camera.h"
#include "libs/render/renderer.h"
#include "libs/render/scene.h"

namespace sylva::render {

// One orthographic view of the bake. The view shows the rectangle centre + [-half_width,
// half_width] right + [-half_height, half_height] up, seen from +dir (dir points toward the
// viewer), depths in [-depth_radius, depth_radius] along dir; it lands in atlas pixels
// [x, x + w) x [y, y + h) (top-left origin). right, up, dir orthonormal, right x up = dir.
struct BakeView {
  Vec3 center = Vec3::Zero();
  Vec3 right = Vec3::UnitX(), up = Vec3::UnitY(), dir = Vec3::UnitZ();
  float half_width = 1, half_height = 1, depth_radius = 1;
  int x = 0, y = 0, w = 1, h = 1;
};

struct BakeOptions {
  int atlas_width = 1, atlas_height = 1;  // pixels; every view's rectangle must lie inside
  int msaa = 4;                           // samples per texel (coverage resolution)
  float line_width_px = 1;                // width of LINES in atlas texels (>= 1)
  float line_alpha_scale = 1;             // LINES' alpha is multiplied by this (0..1]
  // Contexts drawing rows of the atlas side by side (llvmpipe runs vertex work on the calling
  // thread, so one context uses one core for it). The bytes do not depend on this.
  int threads = 1;
  // msaa 1: opaque and masked primitives are drawn into one packed layer and blended ones into
  // layers of their own, composited on read-back (bake_layers.h; llvmpipe's cost per shaded block
  // grows with every attachment). false: every primitive into the three maps' attachments at
  // once, as for msaa > 1. The maps agree within one level per channel (tested).
  bool pack_opaque = true;
};

struct BakedMaps {
  image::Image color;         // sRGB RGB, straight alpha = coverage
  image::Image normal_depth;  // RGB = normal * 0.5 + 0.5 (object space), A = depth
  // Whether opaque and masked primitives went into the packed layer (BakeOptions::pack_opaque):
  // msaa 1 and no opaque or masked line with a fractional alpha (line_alpha_scale < 1), which the
  // packed layer, covered or not, cannot hold.
  bool packed_opaque = false;
};

// What render_octahedral() needs of an impostor (impostor.json + its two PNGs; the names follow
// libs/impostor/impostor_json.h).
struct OctahedralImpostor {
  image::Image color, normal_depth;  // atlas_px x atlas_px each, atlas_px = frames_per_side * frame_px
  ImpostorGeometry geometry;
  std::vector<Mat4> instances{Mat4::Identity()};  // object -> world
};

struct ImpostorDrawOptions {
  int parallax_steps = 16;  // ray-march steps through the depth map per frame (0 = flat frames)
};

class ImpostorRenderer {
 public:
  virtual ~ImpostorRenderer() = default;

  // The real one (its own EGL context, the same device choice as Renderer::create_headless()).
  // Throws RenderUnavailableError.
  static std::unique_ptr<ImpostorRenderer> create_headless();

  // Throws RenderError for invalid options or views (a rectangle outside the atlas, views of one
  // atlas row with different heights, a size beyond the device's limits).
  virtual BakedMaps bake(const Scene& scene, std::span<const BakeView> views, const BakeOptions& options) = 0;

  virtual std::vector<image::Image> render_octahedral(const OctahedralImpostor& impostor,
                                                      std::span<const Camera> cameras,
                                                      const RenderOptions& options,
                                                      const ImpostorDrawOptions& draw = {}) = 0;

  virtual std::string device_description() const = 0;
};

// One ImpostorRenderer per process, created on first use and never destroyed (as the verify
// stage's renderer: tearing EGL down from a static destructor races Mesa's exit handlers). A
// failure to create it is not remembered: every caller gets the same one-line error.
ImpostorRenderer& shared_impostor_renderer();

// The reference shader's sources, exactly as shipped in libs/render/shaders/.
const char* octahedral_impostor_vertex_shader();
const char* octahedral_impostor_fragment_shader();

}  // namespace sylva::render
