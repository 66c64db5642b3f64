// The OpenGL 3.3 core implementation of ImpostorRenderer: the atlas baker and the octahedral
// impostor drawer (impostor_renderer.h has the contract, docs/stages/impostor.md the maps).
//
// Bake. One atlas row of views at a time (bake_rows.h) is drawn into a target as wide as the
// atlas and as tall as the row (bake_target.h: two layouts, by msaa), each primitive one
// instanced draw over the row's views (bake_scene.h, bake_programs.h), and read back into the
// maps. Rows are independent, so contexts of their own draw them side by side
// (BakeOptions::threads). Textures are sampled from their nearest mip level
// (GL_LINEAR_MIPMAP_NEAREST): half the texel fetches of trilinear filtering, which were a third
// of the rasteriser's shader time.
//
// Draw. The reference shader (shaders/octahedral_impostor.*) on one quad per instance
// (octahedral_render.h).
#include "libs/render/impostor_renderer.h"

#include <algorithm>
#include <array>
#include <exception>
#include <map>
#include <mutex>
#include <thread>

#include "libs/render/bake_programs.h"
#include "libs/render/bake_rows.h"
#include "libs/render/bake_scene.h"
#include "libs/render/bake_target.h"
#include "libs/render/gl_context.h"
#include "libs/render/gl_util.h"
#include "libs/render/octahedral_render.h"
#include "libs/render/shaders.h"

namespace sylva::render {
namespace {

using detail::BakeLayout;
using detail::BakePrimitive;
using detail::BakePrograms;
using detail::BakeRow;
using detail::BakeTarget;
using detail::BakeUniforms;
using detail::check_gl;
using detail::CurrentContext;
using detail::GlObjects;

class GlImpostorRenderer final : public ImpostorRenderer {
 public:
  explicit GlImpostorRenderer(std::unique_ptr<detail::GlContext> ctx) : ctx_(std::move(ctx)) {
    CurrentContext current(*ctx_);
    draw_program_ = detail::link_program(detail::kOctahedralImpostorVert, detail::kOctahedralImpostorFrag,
                                         "octahedral impostor");
    limits_ = detail::query_device_limits();
    check_gl("initialisation");
  }

  ~GlImpostorRenderer() override {
    try {
      CurrentContext current(*ctx_);
      bake_programs_.destroy();
      glDeleteProgram(draw_program_);
    } catch (...) {
      // The context goes away with us.
    }
  }

  std::string device_description() const override { return ctx_->description(); }

  BakedMaps bake(const Scene& scene, std::span<const BakeView> views, const BakeOptions& o) override {
    std::lock_guard<std::mutex> lock(mutex_);
    {
      CurrentContext current(*ctx_);
      detail::validate_bake(views, o, limits_);
    }
    const std::vector<BakeRow> rows = detail::plan_rows(views, o);
    const BakeLayout layout = detail::choose_layout(scene, o);
    BakedMaps out;
    out.packed_opaque = layout == BakeLayout::kLayered;
    out.color = image::Image(o.atlas_width, o.atlas_height, {0, 0, 0, 0});
    out.normal_depth = image::Image(o.atlas_width, o.atlas_height, {0, 0, 0, 0});
    // Rows are independent: each context draws every threads-th row (its own copy of the scene),
    // into its own rows of the maps. A row's pixels do not depend on which context drew it.
    const int threads = std::clamp(o.threads, 1, int(rows.size() > 0 ? rows.size() : 1));
    while (int(workers_.size()) < threads - 1)
      workers_.push_back(std::make_unique<Worker>(detail::create_egl_context()));
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(threads), nullptr);
    auto run = [&](int t) {
      try {
        detail::GlContext& ctx = t == 0 ? *ctx_ : *workers_[std::size_t(t - 1)]->ctx;
        BakePrograms& programs = t == 0 ? bake_programs_ : workers_[std::size_t(t - 1)]->programs;
        CurrentContext current(ctx);
        bake_rows(programs, scene, layout, o, rows, std::size_t(t), std::size_t(threads), out);
      } catch (...) {
        errors[std::size_t(t)] = std::current_exception();
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(run, t);
    run(0);
    for (std::thread& th : pool) th.join();
    for (const std::exception_ptr& e : errors)
      if (e) std::rethrow_exception(e);
    return out;
  }

  std::vector<image::Image> render_octahedral(const OctahedralImpostor& imp, std::span<const Camera> cameras,
                                              const RenderOptions& o,
                                              const ImpostorDrawOptions& draw) override {
    std::lock_guard<std::mutex> lock(mutex_);
    CurrentContext current(*ctx_);
    return detail::render_octahedral_views(draw_program_, limits_, imp, cameras, o, draw);
  }

 private:
  // A further context for parallel baking, kept for the renderer's lifetime.
  struct Worker {
    explicit Worker(std::unique_ptr<detail::GlContext> c) : ctx(std::move(c)) {}
    std::unique_ptr<detail::GlContext> ctx;
    BakePrograms programs;
  };

  // Rows first, first + stride, ... of `rows`, with `programs` on the current context.
  void bake_rows(BakePrograms& programs, const Scene& scene, BakeLayout layout, const BakeOptions& o,
                 const std::vector<BakeRow>& rows, std::size_t first, std::size_t stride,
                 BakedMaps& out) const {
    GlObjects gl;
    glGetError();
    std::vector<GLuint> textures;
    for (const Texture& t : scene.textures) {
      textures.push_back(detail::upload_texture(gl, t));
      // The mip level nearest the texel's footprint, filtered bilinearly, not two levels blended:
      // half of llvmpipe's texel fetches (docs/stages/impostor.md, "Texture filtering").
      if (t.mipmaps)
        glTexParameteri(
            GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
            t.min_filter == Filter::kNearest ? GL_NEAREST_MIPMAP_NEAREST : GL_LINEAR_MIPMAP_NEAREST);
    }
    const std::vector<BakePrimitive> prims = detail::upload_bake_scene(gl, scene, layout);
    const bool any_blended =
        std::any_of(prims.begin(), prims.end(), [](const BakePrimitive& p) { return p.blend; });
    check_gl("bake upload");
    // The variants this scene needs, linked once per context; their uniforms.
    std::vector<int> used;
    std::array<BakeUniforms, detail::kBakeVariants> uniforms{};
    for (const BakePrimitive& bp : prims) {
      if (std::find(used.begin(), used.end(), bp.variant) != used.end()) continue;
      used.push_back(bp.variant);
      const GLuint program = programs.get(bp.variant);
      uniforms[std::size_t(bp.variant)] = detail::bake_uniforms(program);
      glUseProgram(program);
      glUniform1i(uniforms[std::size_t(bp.variant)].texture, 0);
    }
    std::map<int, BakeTarget> targets;  // by band height
    detail::RowPixels pixels;           // read-back memory, reused by every row
    for (std::size_t r = first; r < rows.size(); r += stride) {
      const BakeRow& row = rows[r];
      auto it = targets.find(row.h);
      if (it == targets.end())
        it = targets.emplace(row.h, detail::make_bake_target(gl, o.atlas_width, row.h, o.msaa, layout)).first;
      for (int v : used) {
        glUseProgram(programs.program[std::size_t(v)]);
        glUniform4fv(uniforms[std::size_t(v)].views, GLsizei(row.views.size() * 5), row.uniforms.data());
      }
      detail::draw_bake_row(scene, prims, textures, programs, uniforms, GLsizei(row.views.size()), it->second,
                            o, limits_);
      if (layout == BakeLayout::kLayered)
        detail::read_layered_row(it->second, row.y, any_blended, pixels, out);
      else
        detail::read_bake_row(it->second, row.y, pixels, out);
      check_gl("baking");
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  std::unique_ptr<detail::GlContext> ctx_;
  std::vector<std::unique_ptr<Worker>> workers_;  // never destroyed before the renderer (EGL, above)
  std::mutex mutex_;
  BakePrograms bake_programs_;
  GLuint draw_program_ = 0;
  detail::DeviceLimits limits_;
};

}  // namespace

std::unique_ptr<ImpostorRenderer> ImpostorRenderer::create_headless() {
  return std::make_unique<GlImpostorRenderer>(detail::create_egl_context());
}

ImpostorRenderer& shared_impostor_renderer() {
  static std::mutex mu;
  static ImpostorRenderer* renderer = nullptr;
  std::lock_guard<std::mutex> lock(mu);
  if (!renderer) renderer = ImpostorRenderer::create_headless().release();
  return *renderer;
}

}  // namespace sylva::render
