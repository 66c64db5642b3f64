// The OpenGL 3.3 core implementation of Renderer: a view's passes.
//
// The scene's primitives are uploaded once per render_views() call (scene_buffers.h: the
// meshes naming shared geometry stay uploaded between calls), drawn with one program per draw
// state (scene_programs.h) into the kept target (render_target.h). The opaque pass is one
// instanced draw per primitive. Scene::impostors are drawn between the two passes by
// impostor_draw.h (the reference impostor shader, same depth buffer; with hybrid antialiasing
// also given per pixel the farthest depth of its sub-pixels, so that the impostor fragments the
// meshes hide in every sample are not marched). The blend pass draws each (primitive, instance)
// separately, far to near, with the matrices as constant attributes and the elements sorted far
// to near.
//
// Determinism: nothing depends on timing or on hash-table order; every sort is a stable sort
// with an index tie-break; llvmpipe rasterises deterministically.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "libs/render/gl_context.h"
#include "libs/render/gl_util.h"
#include "libs/render/impostor_draw.h"
#include "libs/render/render_target.h"
#include "libs/render/renderer.h"
#include "libs/render/scene_buffers.h"
#include "libs/render/scene_programs.h"

namespace sylva::render {
namespace {

constexpr int kMaxSupersample = 4;

using detail::check_gl;
using detail::clear_to_background;
using detail::CurrentContext;
using detail::gl_mode;
using detail::GlObjects;
using detail::GpuMesh;
using detail::GpuPrimitive;
using detail::RenderTarget;
using detail::SceneAttribute;
using detail::UploadedScene;

// One (primitive, instance) of the blend pass.
struct BlendDraw {
  const GpuPrimitive* prim;
  const GpuMesh* mesh;
  std::size_t instance;
  float depth;  // view-space distance along the viewing direction
  std::size_t order;
};

// The primitive's elements ordered far to near (view depth of their centroid; ties keep file
// order), written as an index list into `out`.
void sort_elements(const Primitive& p, const Mat4& model_view,
                   std::vector<std::pair<float, std::uint32_t>>& keys, std::uint32_t* out) {
  const std::size_t per = p.topology == Topology::kTriangles ? 3 : p.topology == Topology::kLines ? 2 : 1;
  const std::size_t n = p.indices.size() / per;
  const Eigen::RowVector4f row = model_view.row(2);
  keys.resize(n);
  for (std::size_t e = 0; e < n; ++e) {
    Vec3 c = Vec3::Zero();
    for (std::size_t k = 0; k < per; ++k) c += p.positions[p.indices[e * per + k]];
    c /= float(per);
    keys[e] = {-(row * c.homogeneous())(0), std::uint32_t(e)};
  }
  std::stable_sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t e = 0; e < n; ++e)
    for (std::size_t k = 0; k < per; ++k) out[e * per + k] = p.indices[std::size_t(keys[e].second) * per + k];
}

class GlRenderer final : public Renderer {
 public:
  explicit GlRenderer(std::unique_ptr<detail::GlContext> ctx) : ctx_(std::move(ctx)) {
    CurrentContext current(*ctx_);
    passes_.link();
    limits_ = detail::query_device_limits();
    check_gl("initialisation");
  }

  ~GlRenderer() override {
    try {
      CurrentContext current(*ctx_);
      programs_.destroy();
      buffers_.destroy();
      kept_target_.reset();
      passes_.destroy();
      impostors_.destroy();
    } catch (...) {
      // The context is going away with us; nothing else to release.
    }
  }

  std::string device_description() const override { return ctx_->description(); }

  std::size_t kept_geometry() const override { return buffers_.kept(); }
  std::size_t kept_impostor_atlases() const override { return impostors_.kept(); }

  void prepare(const Scene& scene, const RenderOptions& options) override {
    std::lock_guard<std::mutex> lock(mutex_);
    CurrentContext current(*ctx_);
    validate(options);
    GlObjects gl;  // the impostor drawer's per-call objects; the kept ones outlive it
    glGetError();
    kept_target_.for_options(options);
    buffers_.drop_dead();
    buffers_.keep(scene);
    impostors_.upload(gl, scene.impostors, limits_.max_texture_size,
                      detail::hybrid(options) && options.impostor_hidden_discard);
    check_gl("upload");
  }

  std::vector<image::Image> render_views(const Scene& scene, std::span<const Camera> cameras,
                                         const RenderOptions& options) override {
    std::lock_guard<std::mutex> lock(mutex_);
    CurrentContext current(*ctx_);
    validate(options);
    GlObjects gl;
    glGetError();  // start from a clean error state
    const RenderTarget& target = kept_target_.for_options(options);
    const UploadedScene up = buffers_.upload(gl, scene);
    const detail::ImpostorDrawer::Uploaded imp =
        impostors_.upload(gl, scene.impostors, limits_.max_texture_size,
                          detail::hybrid(options) && options.impostor_hidden_discard);
    check_gl("upload");
    std::vector<image::Image> images;
    images.reserve(cameras.size());
    for (const Camera& cam : cameras) {
      draw(scene, up, imp, cam, options, target);
      images.push_back(passes_.read_back(target, options));
      check_gl("drawing");
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return images;
  }

 private:
  void validate(const RenderOptions& o) const {
    const GLint max_size = limits_.max_renderbuffer_size, max_samples = limits_.max_samples;
    if (o.supersample < 1 || o.supersample > kMaxSupersample)
      throw RenderError("supersample " + std::to_string(o.supersample) + " is not supported (1.." +
                        std::to_string(kMaxSupersample) + ")");
    const int k = o.supersample;
    if (o.width < 1 || o.height < 1 || o.width > max_size / k || o.height > max_size / k)
      throw RenderError("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                        (k > 1 ? " supersampled " + std::to_string(k) + "x" : std::string()) +
                        " is outside 1.." + std::to_string(max_size));
    if (o.msaa < 1 || o.msaa > max_samples)
      throw RenderError("msaa " + std::to_string(o.msaa) + " is not supported (this device allows 1.." +
                        std::to_string(max_samples) + ")");
    if (k > 1 && o.msaa > 1 && o.msaa != k * k)
      throw RenderError("supersample " + std::to_string(k) + " needs msaa 1 or " + std::to_string(k * k) +
                        " (the samples of a pixel are its sub-pixels), got msaa " + std::to_string(o.msaa));
    if (o.background.a != 0 && o.background.a != 255)
      throw RenderError("background alpha must be 0 (transparent) or 255 (opaque)");
    if (!(o.line_width_px > 0) || !(o.default_point_size_px > 0) || !(o.min_point_size_px > 0))
      throw RenderError("line width and point sizes must be positive");
  }

  // One view: clear, pass 1, impostors, pass 2.
  void draw(const Scene& scene, const UploadedScene& up, const detail::ImpostorDrawer::Uploaded& imp,
            const Camera& cam, const RenderOptions& o, const RenderTarget& t) {
    begin_view(o, t);
    const float aspect = float(o.width) / float(o.height);
    const Mat4 view = cam.view_matrix();
    // Supersampled, points keep their size in output pixels: k drawn pixels.
    const float k = float(o.supersample);
    programs_.begin_view({view, cam.projection_matrix(aspect), float(t.height), o.default_point_size_px * k,
                          o.min_point_size_px * k, o.lighting.ambient, o.lighting.light_color,
                          o.lighting.direction_to_light.norm() > 0
                              ? Vec3(o.lighting.direction_to_light.normalized())
                              : Vec3::UnitY()});
    std::vector<BlendDraw> blended = draw_opaque(scene, up, view);
    // Impostors: behind what pass 1 drew where it is nearer, blended over it elsewhere.
    if (!scene.impostors.empty()) {
      if (detail::hybrid(o)) {
        if (o.impostor_hidden_discard) passes_.farthest_depth(t, o);
        passes_.to_samples(t, o);
        impostors_.draw(scene.impostors, imp, cam, aspect, o.lighting,
                        o.impostor_hidden_discard ? t.farthest_texture : 0);
        passes_.from_samples(t, o);
      } else {
        impostors_.draw(scene.impostors, imp, cam, aspect, o.lighting);
      }
      programs_.forget_current();  // the impostor drawer used its own
    }
    draw_blended(scene, up, view, blended);
    glBindVertexArray(0);
  }

  // Binds the target and clears it; the state pass 1 starts from.
  void begin_view(const RenderOptions& o, const RenderTarget& t) const {
    glBindFramebuffer(GL_FRAMEBUFFER, t.draw_fbo);
    glViewport(0, 0, t.width, t.height);
    // Supersampled, lines keep their width in output pixels: k drawn pixels.
    const float k = float(o.supersample);
    clear_to_background(o.background);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    glDisable(GL_BLEND);
    glEnable(GL_PROGRAM_POINT_SIZE);
    if (o.msaa > 1 && o.supersample == 1) {
      glEnable(GL_MULTISAMPLE);
    } else {
      glDisable(GL_MULTISAMPLE);
    }
    glLineWidth(std::clamp(o.line_width_px * k, limits_.line_width_range[0], limits_.line_width_range[1]));
  }

  // Pass 1: opaque and masked, one instanced draw per primitive. Returns the blend pass's draws
  // (every blended primitive x instance, in scene order, with its depth).
  std::vector<BlendDraw> draw_opaque(const Scene& scene, const UploadedScene& up, const Mat4& view) {
    std::vector<BlendDraw> blended;
    for (const GpuMesh& gm : up.meshes) {
      const std::size_t instances = gm.source->instances.size();
      for (const GpuPrimitive& gp : gm.primitives) {
        if (gp.index_count == 0) continue;
        if (gp.blend) {
          const Vec3 c = gp.source->bounds().center();
          for (std::size_t i = 0; i < instances; ++i) {
            const Vec3 w = (gm.source->instances[i] * c.homogeneous()).hnormalized();
            const float depth = -(view * w.homogeneous())(2);
            blended.push_back({&gp, &gm, i, depth, blended.size()});
          }
          continue;
        }
        programs_.set_primitive_state(scene, up.textures, *gp.source, gm.mirrored);
        glBindVertexArray(gp.vao_instanced);
        glDrawElementsInstanced(gl_mode(gp.source->topology), gp.index_count, GL_UNSIGNED_INT, nullptr,
                                GLsizei(instances));
      }
    }
    return blended;
  }

  // Pass 2: blended, far to near (Zhang et al. 2017, 6.1), depth test on, depth write off.
  // Every draw's sorted elements go into one index buffer, uploaded once before the first
  // draw: rewriting one buffer per draw would make the driver finish every earlier draw that
  // reads it first (llvmpipe: a full flush and wait per blended instance).
  void draw_blended(const Scene& scene, const UploadedScene& up, const Mat4& view,
                    std::vector<BlendDraw>& blended) {
    if (blended.empty()) return;
    std::stable_sort(blended.begin(), blended.end(),
                     [](const BlendDraw& a, const BlendDraw& b) { return a.depth > b.depth; });
    std::vector<std::size_t> offset(blended.size() + 1, 0);
    for (std::size_t i = 0; i < blended.size(); ++i)
      offset[i + 1] = offset[i] + blended[i].prim->source->indices.size();
    std::vector<std::uint32_t> sorted(offset.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blended.size()), [&](const auto& r) {
      std::vector<std::pair<float, std::uint32_t>> keys;
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const BlendDraw& d = blended[i];
        sort_elements(*d.prim->source, view * d.mesh->source->instances[d.instance], keys,
                      &sorted[offset[i]]);
      }
    });
    // A new data store per view (glBufferData), so no earlier view's draw is waited for.
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, up.blend_indices);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(sorted.size() * sizeof(std::uint32_t)), sorted.data(),
                 GL_STREAM_DRAW);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    for (std::size_t i = 0; i < blended.size(); ++i) {
      const BlendDraw& d = blended[i];
      const Primitive& p = *d.prim->source;
      programs_.set_primitive_state(scene, up.textures, p, d.mesh->mirrored);
      glBindVertexArray(d.prim->vao_single);
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, up.blend_indices);
      const float* inst = &d.mesh->instance_data[d.instance * detail::kInstanceFloats];
      for (GLuint c = 0; c < 4; ++c) glVertexAttrib4fv(SceneAttribute::kModel + c, inst + c * 4);
      for (GLuint c = 0; c < 3; ++c) glVertexAttrib3fv(SceneAttribute::kNormalMatrix + c, inst + 16 + c * 3);
      glDrawElements(gl_mode(p.topology), d.prim->index_count, GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(std::uintptr_t(offset[i] * sizeof(std::uint32_t))));
    }
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
  }

  std::unique_ptr<detail::GlContext> ctx_;
  std::mutex mutex_;
  detail::SceneBuffers buffers_;
  detail::KeptTarget kept_target_;
  detail::ScenePrograms programs_;
  detail::TargetPasses passes_;
  detail::ImpostorDrawer impostors_;
  detail::DeviceLimits limits_;
};

}  // namespace

std::unique_ptr<Renderer> Renderer::create_headless() {
  return std::make_unique<GlRenderer>(detail::create_egl_context());
}

}  // namespace sylva::render
