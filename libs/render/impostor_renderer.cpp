// The OpenGL 3.3 core implementation of ImpostorRenderer: the atlas baker and the octahedral
// impostor drawer (impostor_renderer.h has the contract, docs/stages/impostor.md the maps).
//
// Bake. One atlas row of views at a time is drawn into a target as wide as the atlas and as tall
// as the row. Each primitive is one instanced draw over the row's views: the vertex shader takes
// the view's frame from a uniform array by gl_InstanceID (every view frames the whole source, so
// nothing needs clipping to its rectangle). Opaque and masked primitives first (depth test and
// write), then blended ones (depth test, no write, alpha over), as the scene renderer's passes.
// Blended primitives are drawn in file order without sorting: a primitive has one material
// colour, and "over" with equal colours does not depend on order. Blended LINES are drawn with
// each run of coincident segments merged into one line of their composite (line_merge.h), by a
// program variant that carries the copies' normals. Two target layouts (BakeLayout):
//  - kLayered (msaa 1, the stage's default): opaque and masked primitives write one packed
//    RGBA16UI texel (colour, normal, depth rounded to 8 bits and a covered flag), blended ones
//    blend into three RGBA16 layers of their own; read-back composites the lines over the opaque
//    texel (bake_layers.h). llvmpipe's CPU per shaded 4 x 4 block grows with every attachment
//    and its bytes, and 93 % of an adult tree's primitives are opaque or masked.
//  - kBlended (msaa > 1): three colour attachments in one pass (colour RGBA8, normal RGBA16,
//    depth RGBA16; 16-bit so that dividing the resolved, coverage-weighted values by the
//    coverage keeps 8 bits of precision). Every fragment writes its alpha as the alpha of all
//    three outputs, so after the MSAA resolve each attachment holds value * coverage (the
//    background is 0): dividing by the attachment's alpha gives the covered samples' average.
// Textures are sampled from their nearest mip level (GL_LINEAR_MIPMAP_NEAREST): half the texel
// fetches of trilinear filtering, which were a third of the rasteriser's shader time.
//
// Draw. The reference shader (shaders/octahedral_impostor.*) on one quad per instance.
#include "libs/render/impostor_renderer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <exception>
#include <map>
#include <mutex>
#include <thread>

#include "libs/render/bake_layers.h"
#include "libs/render/gl_context.h"
#include "libs/render/gl_util.h"
#include "libs/render/impostor_atlas.h"
#include "libs/render/impostor_draw.h"
#include "libs/render/line_merge.h"

namespace sylva::render {
namespace {

using detail::check_gl;
using detail::CurrentContext;
using detail::gl_mode;
using detail::GlObjects;
using detail::upload_array;

// ---- Bake shaders ------------------------------------------------------------------------------

// One source, a program per variant (BakeVariant below): MERGED_LINES (the lines of line_merge.h
// with their extra normals), IS_LINES (other lines: their normal turned toward the viewer),
// HAS_NORMALS, HAS_COLORS, HAS_TEXTURE, OPAQUE_LAYER (the packed layer's output, BakeLayout). A
// variant passes on only the varyings it reads: llvmpipe sets up and interpolates every varying
// of every tiny triangle, and a leaf (normals, texture, no colours) needs 6 of the 16 floats (the
// view direction only lines read; measured: docs/performance.md). The variants compute what one
// program with those switches as uniforms computed, to the bit.
constexpr const char* kBakeVertexShader = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_texcoord;
layout(location = 3) in vec4 a_color;
#if MERGED_LINES
// Merged lines (line_merge.h): the second and third copies' normals and the number of copies.
layout(location = 4) in vec3 a_normal1;
layout(location = 5) in vec3 a_normal2;
layout(location = 6) in float a_copies;
#endif

uniform mat4 u_model;
uniform mat3 u_normal_matrix;
// Per view of the row (gl_InstanceID): centre, right / half width, up / half height,
// dir / depth radius, and the view's rectangle in NDC (centre x, y, half width, half height).
uniform vec4 u_views[5 * 64];

#if HAS_NORMALS
out vec3 v_normal;
#else
out vec3 v_world;
#endif
#if MERGED_LINES
out vec3 v_normal1;
out vec3 v_normal2;
flat out float v_copies;
#endif
#if HAS_TEXTURE
out vec2 v_texcoord;
#endif
#if HAS_COLORS
out vec4 v_color;
#endif
flat out vec3 v_dir;
out float v_depth;

void main() {
  int b = gl_InstanceID * 5;
  vec3 c = u_views[b].xyz;
  vec3 r = u_views[b + 1].xyz;
  vec3 u = u_views[b + 2].xyz;
  vec3 d = u_views[b + 3].xyz;
  vec4 rect = u_views[b + 4];
  vec4 world = u_model * vec4(a_position, 1.0);
  vec3 a = world.xyz - c;
  float s = dot(a, r), t = dot(a, u), z = dot(a, d);
  // Every view frames the whole source (layouts fit the bounding sphere), so nothing reaches a
  // neighbouring view's rectangle and no clipping is needed.
  gl_Position = vec4(rect.x + s * rect.z, rect.y + t * rect.w, -z, 1.0);
#if HAS_NORMALS
  v_normal = u_normal_matrix * a_normal;
#else
  v_world = world.xyz;
#endif
#if MERGED_LINES
  v_normal1 = u_normal_matrix * a_normal1;
  v_normal2 = u_normal_matrix * a_normal2;
  v_copies = a_copies;
#endif
#if HAS_TEXTURE
  v_texcoord = a_texcoord;
#endif
#if HAS_COLORS
  v_color = a_color;
#endif
  v_dir = normalize(d);
  v_depth = z;
}
)";

constexpr const char* kBakeFragmentShader = R"(
#if HAS_NORMALS
in vec3 v_normal;
#else
in vec3 v_world;
#endif
#if MERGED_LINES
in vec3 v_normal1;
in vec3 v_normal2;
flat in float v_copies;
#endif
#if HAS_TEXTURE
in vec2 v_texcoord;
#endif
#if HAS_COLORS
in vec4 v_color;
#endif
flat in vec3 v_dir;
in float v_depth;

uniform vec4 u_base_color;
uniform sampler2D u_texture;
uniform int u_alpha_mode;  // 0 opaque, 1 mask, 2 blend
uniform float u_alpha_cutoff;
uniform bool u_two_sided;     // glTF doubleSided triangles: a back face uses the reversed normal
uniform bool u_mirrored;      // the instance matrix mirrors: clockwise is the front
uniform float u_alpha_scale;  // lines thinner than a texel: their coverage spread over one texel

#if OPAQUE_LAYER
// The opaque layer (msaa 1, opaque and masked primitives): every map's 8-bit value in one
// unsigned 16-bit RGBA texel (BakeLayout::kLayered in the renderer).
layout(location = 3) out uvec4 o_packed;
#else
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_depth;
#endif

float to_srgb(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

void main() {
  vec4 base = u_base_color;
#if HAS_COLORS
  base *= v_color;
#endif
#if HAS_TEXTURE
  base *= texture(u_texture, v_texcoord);
#endif
  if (u_alpha_mode == 1) {
    if (base.a < u_alpha_cutoff) discard;
    base.a = 1.0;
  } else if (u_alpha_mode == 0) {
    base.a = 1.0;
  }
  base.a *= u_alpha_scale;
  // The scene renderer's rules (gl_renderer.cpp, glTF 2.0 3.9.2): the front face is the
  // counter-clockwise one (clockwise under a mirroring matrix), a double-sided back face is lit
  // with the reversed normal; without normals, the face normal, which faces the view.
  bool front = gl_FrontFacing != u_mirrored;
#if HAS_NORMALS
  vec3 n = normalize(v_normal);
  if (u_two_sided && !front) n = -n;
#else
  vec3 n = normalize(cross(dFdx(v_world), dFdy(v_world)));
#endif
  // Lines stand for twigs, which the full detail draws as lit cylinders: bake their normals
  // turned toward the view (the renderer draws LINES unlit, as three.js does; an impostor is lit).
#if IS_LINES
  if (dot(n, v_dir) < 0.0) n = -n;
#elif MERGED_LINES
  int copies = int(v_copies + 0.5);
  if (copies <= 1) {
    if (dot(n, v_dir) < 0.0) n = -n;
  } else {
    // k coincident lines of alpha a drawn as one (line_merge.h): the copy drawn last weighs a,
    // the one before a (1 - a), ...; together they cover 1 - (1 - a)^k, and their normals (each
    // turned toward the view) average with the same weights, as k overs would composite them.
    float a = base.a, w = a, cover = 0.0;
    vec3 sum = vec3(0.0);
    for (int j = copies - 1; j >= 0; --j) {
      vec3 nj = n;
#if HAS_NORMALS
      nj = normalize(j == 0 ? v_normal : j == 1 ? v_normal1 : v_normal2);
#endif
      if (dot(nj, v_dir) < 0.0) nj = -nj;
      sum += w * nj;
      cover += w;
      w *= 1.0 - a;
    }
    if (cover > 0.0) n = sum / cover;
    base.a = cover;
  }
#endif
#if OPAQUE_LAYER
  // Covered (alpha 1): colour, normal and depth as the maps store them, rounded to 8 bits, and
  // 0xFF in the top byte of alpha (covered; the layer is cleared to 0).
  uvec3 c8 = uvec3(vec3(to_srgb(base.r), to_srgb(base.g), to_srgb(base.b)) * 255.0 + 0.5);
  uvec3 n8 = uvec3(clamp(n * 0.5 + 0.5, 0.0, 1.0) * 255.0 + 0.5);
  uint d8 = uint(clamp(v_depth * 0.5 + 0.5, 0.0, 1.0) * 255.0 + 0.5);
  o_packed = uvec4(c8.r | (c8.g << 8), c8.b | (n8.x << 8), n8.y | (n8.z << 8), d8 | 0xFF00u);
#else
  o_color = vec4(to_srgb(base.r), to_srgb(base.g), to_srgb(base.b), base.a);
  o_normal = vec4(n * 0.5 + 0.5, base.a);
  o_depth = vec4(clamp(v_depth * 0.5 + 0.5, 0.0, 1.0), 0.0, 0.0, base.a);
#endif
}
)";

// Which bake program draws a primitive (see kBakeVertexShader).
struct BakeVariant {
  bool merged_lines = false, normals = false, colors = false, texture = false, opaque_layer = false;
  bool lines = false;  // LINES that are not merged_lines
  int key() const {
    return int(merged_lines) | int(normals) << 1 | int(colors) << 2 | int(texture) << 3 |
           int(opaque_layer) << 4 | int(lines) << 5;
  }
};
constexpr int kBakeVariants = 64;

GLuint link_bake_program(int key) {
  auto source = [&](const char* body) {
    std::string s = "#version 330 core\n";
    for (auto [bit, name] : {std::pair{1, "MERGED_LINES"},
                             {2, "HAS_NORMALS"},
                             {4, "HAS_COLORS"},
                             {8, "HAS_TEXTURE"},
                             {16, "OPAQUE_LAYER"},
                             {32, "IS_LINES"}})
      s += std::string("#define ") + name + ((key & bit) ? " 1\n" : " 0\n");
    return s + body;
  };
  return detail::link_program(source(kBakeVertexShader).c_str(), source(kBakeFragmentShader).c_str(),
                              "impostor bake (variant " + std::to_string(key) + ")");
}

// A context's bake programs, linked when first needed (0 = not yet).
struct BakePrograms {
  std::array<GLuint, kBakeVariants> program{};
};

enum : GLuint {
  kPosition = 0,
  kNormal = 1,
  kTexcoord = 2,
  kColor = 3,
  kNormal1 = 4,
  kNormal2 = 5,
  kCopies = 6
};
constexpr std::size_t kMaxRowViews = 64;  // u_views[5 * 64] in the bake vertex shader

// ---- Uploaded bake scene -----------------------------------------------------------------------

struct BakePrimitive {
  const Primitive* source = nullptr;
  const Mesh* mesh = nullptr;
  GLuint vao = 0;
  GLsizei index_count = 0;  // indices, or vertices when not indexed
  int variant = 0;          // BakeVariant::key()
  bool indexed = true;      // false: merged lines (line_merge.h), drawn as arrays
  bool blend = false;
};

void check_bake_primitive(const Scene& scene, const Primitive& p) {
  const std::size_t n = p.positions.size();
  auto bad = [&](const std::string& what) {
    throw RenderError("invalid primitive in scene '" + scene.source + "': " + what);
  };
  if ((!p.normals.empty() && p.normals.size() != n) || (!p.texcoords.empty() && p.texcoords.size() != n) ||
      (!p.colors.empty() && p.colors.size() != n))
    bad("attribute arrays differ in length from positions");
  for (std::uint32_t i : p.indices)
    if (i >= n) bad("index " + std::to_string(i) + " out of range");
  if (p.material >= 0 && std::size_t(p.material) >= scene.materials.size()) bad("material out of range");
  if (p.material >= 0) {
    const int t = scene.materials[std::size_t(p.material)].base_color_texture;
    if (t >= 0 && std::size_t(t) >= scene.textures.size()) bad("texture out of range");
  }
}

// ---- The renderer ------------------------------------------------------------------------------

class GlImpostorRenderer final : public ImpostorRenderer {
 public:
  explicit GlImpostorRenderer(std::unique_ptr<detail::GlContext> ctx) : ctx_(std::move(ctx)) {
    CurrentContext current(*ctx_);

    draw_program_ = detail::link_program(octahedral_impostor_vertex_shader(),
                                         octahedral_impostor_fragment_shader(), "octahedral impostor");
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples_);
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size_);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture_size_);
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, line_width_range_);
    check_gl("initialisation");
  }

  ~GlImpostorRenderer() override {
    try {
      CurrentContext current(*ctx_);
      for (GLuint p : bake_programs_.program)
        if (p) glDeleteProgram(p);
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
      validate_bake(views, o);
    }
    const std::vector<BakeRow> rows = plan_rows(views, o);
    const BakeLayout layout = choose_layout(scene, o);
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
    validate_draw(imp, o);
    const ImpostorGeometry& g = imp.geometry;
    GlObjects gl;
    glGetError();
    const DrawTarget target = make_draw_target(gl, o);
    const PremultipliedMaps pm = premultiply(imp.color, imp.normal_depth);
    const GLuint color = upload_atlas(gl, pm.color, true, g.mip_levels);
    const GLuint normal = upload_atlas(gl, pm.normal_depth, false, g.mip_levels);

    // One quad (two triangles), instanced per impostor.
    const std::vector<float> corners = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
    std::vector<float> models;
    for (const Mat4& m : imp.instances) models.insert(models.end(), m.data(), m.data() + 16);
    const GLuint vao = gl.vertex_array();
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, upload_array(gl, GL_ARRAY_BUFFER, corners));
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindBuffer(GL_ARRAY_BUFFER, upload_array(gl, GL_ARRAY_BUFFER, models));
    for (GLuint c = 0; c < 4; ++c) {
      glEnableVertexAttribArray(1 + c);
      glVertexAttribPointer(1 + c, 4, GL_FLOAT, GL_FALSE, 16 * sizeof(float),
                            reinterpret_cast<const void*>(std::uintptr_t(c * 4 * sizeof(float))));
      glVertexAttribDivisor(1 + c, 1);
    }
    check_gl("impostor upload");

    glUseProgram(draw_program_);
    auto u = [&](const char* n) { return glGetUniformLocation(draw_program_, n); };
    detail::set_impostor_uniforms(draw_program_, g, draw.parallax_steps);
    glUniform3fv(u("u_ambient"), 1, o.lighting.ambient.data());
    glUniform3fv(u("u_light_color"), 1, o.lighting.light_color.data());
    const Vec3 l =
        o.lighting.direction_to_light.norm() > 0 ? o.lighting.direction_to_light.normalized() : Vec3::UnitY();
    glUniform3fv(u("u_light_dir"), 1, l.data());
    glUniform1i(u("u_color"), 0);
    glUniform1i(u("u_normal_depth"), 1);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, color);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, normal);
    glActiveTexture(GL_TEXTURE0);

    // Far to near by the instance's distance, so that blended instances composite correctly.
    std::vector<image::Image> images;
    const float aspect = float(o.width) / float(o.height);
    for (const Camera& cam : cameras) {
      glBindFramebuffer(GL_FRAMEBUFFER, target.draw_fbo);
      glViewport(0, 0, o.width, o.height);
      const bool transparent = o.background.a == 0;
      glClearColor(transparent ? 0.f : o.background.r / 255.f, transparent ? 0.f : o.background.g / 255.f,
                   transparent ? 0.f : o.background.b / 255.f, o.background.a / 255.f);
      glClearDepth(1.0);
      glDepthMask(GL_TRUE);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      glDisable(GL_CULL_FACE);
      glEnable(GL_BLEND);
      glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
      glDepthMask(GL_FALSE);
      if (o.msaa > 1)
        glEnable(GL_MULTISAMPLE);
      else
        glDisable(GL_MULTISAMPLE);
      glUniformMatrix4fv(u("u_view"), 1, GL_FALSE, cam.view_matrix().data());
      glUniformMatrix4fv(u("u_proj"), 1, GL_FALSE, cam.projection_matrix(aspect).data());
      glUniform3fv(u("u_eye"), 1, cam.eye.data());
      sort_instances(imp, cam, gl, vao);
      glDrawArraysInstanced(GL_TRIANGLES, 0, 6, GLsizei(imp.instances.size()));
      glDepthMask(GL_TRUE);
      glDisable(GL_BLEND);
      images.push_back(read_draw_target(target, o));
      check_gl("impostor drawing");
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return images;
  }

 private:
  struct BakeUniforms {
    GLint model, normal_matrix, views, base_color, texture, alpha_mode, alpha_cutoff, two_sided, mirrored,
        alpha_scale;
  };
  static BakeUniforms bake_uniforms(GLuint program) {
    auto u = [&](const char* n) { return glGetUniformLocation(program, n); };
    return {u("u_model"),      u("u_normal_matrix"), u("u_views[0]"),  u("u_base_color"), u("u_texture"),
            u("u_alpha_mode"), u("u_alpha_cutoff"),  u("u_two_sided"), u("u_mirrored"),   u("u_alpha_scale")};
  }

  // How the row targets hold the maps. kBlended: three attachments (colour RGBA8, normal RGBA16,
  // depth RGBA16), every primitive drawn into all three with its alpha as each one's alpha, the
  // maps the attachments divided by their alpha after the resolve (any msaa). kLayered (msaa 1):
  // opaque and masked primitives into one packed RGBA16UI attachment, blended ones into three
  // RGBA16 attachments of their own, composited on read-back (bake_layers.h); a seventh
  // less rasteriser CPU on an adult tree. Not kLayered when an opaque or masked line carries a fractional
  // alpha (line_alpha_scale < 1): the packed layer has no coverage but covered or not.
  enum class BakeLayout { kBlended, kLayered };
  static BakeLayout choose_layout(const Scene& scene, const BakeOptions& o) {
    if (o.msaa != 1 || !o.pack_opaque) return BakeLayout::kBlended;
    if (o.line_alpha_scale < 1)
      for (const Mesh& mesh : scene.meshes)
        for (const Primitive& p : mesh.primitives)
          if (p.topology == Topology::kLines && !is_blended(scene, p)) return BakeLayout::kBlended;
    return BakeLayout::kLayered;
  }
  static bool is_blended(const Scene& scene, const Primitive& p) {
    return p.material >= 0 && scene.materials[std::size_t(p.material)].alpha_mode == AlphaMode::kBlend;
  }

  struct BakeTarget {
    int width = 0, height = 0;
    GLuint draw_fbo = 0, resolve_fbo = 0;
    BakeLayout layout = BakeLayout::kBlended;
  };

  // A row's attachments as read back (RGBA each), kept from row to row: allocating them per row
  // cost more CPU in page faults than reading them (docs/performance.md). kBlended: color (8-bit),
  // normal, depth; kLayered: packed, and the blended layers in color16, normal, depth.
  struct RowPixels {
    std::vector<std::uint8_t> color;
    std::vector<std::uint16_t> normal, depth, packed, color16;
  };

  // One atlas row: the views that share its y and height, and their uniforms.
  struct BakeRow {
    int y = 0, h = 0;
    std::vector<std::size_t> views;
    std::vector<float> uniforms;  // 5 vec4 per view, see the bake vertex shader
  };

  // A further context for parallel baking, kept for the renderer's lifetime.
  struct Worker {
    explicit Worker(std::unique_ptr<detail::GlContext> c) : ctx(std::move(c)) {}
    std::unique_ptr<detail::GlContext> ctx;
    BakePrograms programs;
  };

  static std::vector<BakeRow> plan_rows(std::span<const BakeView> views, const BakeOptions& o) {
    std::map<std::pair<int, int>, std::vector<std::size_t>> by_row;  // (y, h) -> views, in view order
    for (std::size_t v = 0; v < views.size(); ++v) by_row[{views[v].y, views[v].h}].push_back(v);
    std::vector<BakeRow> rows;
    for (const auto& [key, idx] : by_row) {
      if (idx.size() > kMaxRowViews)
        throw RenderError("an atlas row holds " + std::to_string(idx.size()) + " views; at most " +
                          std::to_string(kMaxRowViews) + " are supported");
      BakeRow row;
      row.y = key.first;
      row.h = key.second;
      row.views = idx;
      for (std::size_t v : idx) {
        const BakeView& bv = views[v];
        const Vec3 r = bv.right / bv.half_width, u = bv.up / bv.half_height, d = bv.dir / bv.depth_radius;
        const float cx = (bv.x + 0.5f * bv.w) / float(o.atlas_width) * 2 - 1;
        const float hw = float(bv.w) / float(o.atlas_width);
        const float hh = float(bv.h) / float(row.h);  // the row fills its band's height
        const float vals[20] = {
            bv.center.x(), bv.center.y(), bv.center.z(), 0, r.x(), r.y(), r.z(), 0, u.x(), u.y(), u.z(), 0,
            d.x(),         d.y(),         d.z(),         0, cx,    0.f,   hw,    hh};
        row.uniforms.insert(row.uniforms.end(), vals, vals + 20);
      }
      rows.push_back(std::move(row));
    }
    return rows;
  }

  // Rows first, first + stride, ... of `rows`, with `program` on the current context.
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
    const std::vector<BakePrimitive> prims = upload_bake_scene(gl, scene, layout);
    const bool any_blended =
        std::any_of(prims.begin(), prims.end(), [](const BakePrimitive& p) { return p.blend; });
    check_gl("bake upload");
    // The variants this scene needs, linked once per context; their uniforms.
    std::vector<int> used;
    std::array<BakeUniforms, kBakeVariants> uniforms{};
    for (const BakePrimitive& bp : prims) {
      if (std::find(used.begin(), used.end(), bp.variant) != used.end()) continue;
      used.push_back(bp.variant);
      GLuint& program = programs.program[std::size_t(bp.variant)];
      if (!program) program = link_bake_program(bp.variant);
      uniforms[std::size_t(bp.variant)] = bake_uniforms(program);
      glUseProgram(program);
      glUniform1i(uniforms[std::size_t(bp.variant)].texture, 0);
    }
    std::map<int, BakeTarget> targets;  // by band height
    RowPixels pixels;                   // read-back memory, reused by every row
    for (std::size_t r = first; r < rows.size(); r += stride) {
      const BakeRow& row = rows[r];
      auto it = targets.find(row.h);
      if (it == targets.end())
        it = targets.emplace(row.h, make_bake_target(gl, o.atlas_width, row.h, o.msaa, layout)).first;
      for (int v : used) {
        glUseProgram(programs.program[std::size_t(v)]);
        glUniform4fv(uniforms[std::size_t(v)].views, GLsizei(row.views.size() * 5), row.uniforms.data());
      }
      draw_bake_row(scene, prims, textures, programs, uniforms, GLsizei(row.views.size()), it->second, o);
      if (layout == BakeLayout::kLayered)
        read_layered_row(it->second, row.y, any_blended, pixels, out);
      else
        read_bake_row(it->second, row.y, pixels, out);
      check_gl("baking");
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  void validate_bake(std::span<const BakeView> views, const BakeOptions& o) const {
    if (o.atlas_width < 1 || o.atlas_height < 1 || o.atlas_width > max_size_ || o.atlas_height > max_size_)
      throw RenderError("atlas size " + std::to_string(o.atlas_width) + "x" + std::to_string(o.atlas_height) +
                        " is outside 1.." + std::to_string(max_size_));
    if (o.msaa < 1 || o.msaa > max_samples_)
      throw RenderError("msaa " + std::to_string(o.msaa) + " is not supported (this device allows 1.." +
                        std::to_string(max_samples_) + ")");
    if (!(o.line_width_px >= 1) || !(o.line_alpha_scale > 0 && o.line_alpha_scale <= 1))
      throw RenderError("line width must be at least 1 texel and the line alpha scale in (0, 1]");
    for (std::size_t v = 0; v < views.size(); ++v) {
      const BakeView& b = views[v];
      if (b.x < 0 || b.y < 0 || b.w < 1 || b.h < 1 || b.x + b.w > o.atlas_width || b.y + b.h > o.atlas_height)
        throw RenderError("bake view " + std::to_string(v) + " lies outside the atlas");
      if (!(b.half_width > 0) || !(b.half_height > 0) || !(b.depth_radius > 0))
        throw RenderError("bake view " + std::to_string(v) + " has a non-positive extent");
    }
  }

  BakeTarget make_bake_target(GlObjects& gl, int w, int h, int msaa, BakeLayout layout) const {
    BakeTarget t;
    t.width = w;
    t.height = h;
    t.layout = layout;
    const GLenum formats[3] = {GL_RGBA8, GL_RGBA16, GL_RGBA16};
    auto attach = [&](GLuint fbo, GLenum attachment, GLenum format, int samples) {
      const GLuint rb = gl.renderbuffer();
      glBindRenderbuffer(GL_RENDERBUFFER, rb);
      if (samples > 1) {
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, w, h);
      } else {
        glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
      }
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, rb);
    };
    const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    t.draw_fbo = gl.framebuffer();
    if (layout == BakeLayout::kLayered) {
      // The blended layers (colour, normal, depth: RGBA16) and the packed opaque layer.
      for (int a = 0; a < 3; ++a) attach(t.draw_fbo, bufs[a], GL_RGBA16, 1);
      attach(t.draw_fbo, GL_COLOR_ATTACHMENT3, GL_RGBA16UI, 1);
      attach(t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, 1);
      if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RenderError("cannot create a " + std::to_string(w) + "x" + std::to_string(h) + " bake target");
      t.resolve_fbo = t.draw_fbo;
      return t;
    }
    for (int a = 0; a < 3; ++a) attach(t.draw_fbo, bufs[a], formats[a], msaa);
    attach(t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, msaa);
    glDrawBuffers(3, bufs);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("cannot create a " + std::to_string(w) + "x" + std::to_string(h) + " bake target");
    t.resolve_fbo = t.draw_fbo;
    if (msaa > 1) {
      t.resolve_fbo = gl.framebuffer();
      for (int a = 0; a < 3; ++a) attach(t.resolve_fbo, bufs[a], formats[a], 1);
      glDrawBuffers(3, bufs);
      if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RenderError("cannot create the bake resolve target");
    }
    return t;
  }

  std::vector<BakePrimitive> upload_bake_scene(GlObjects& gl, const Scene& scene, BakeLayout layout) const {
    std::vector<BakePrimitive> out;
    for (const Mesh& mesh : scene.meshes) {
      if (mesh.instances.empty()) continue;
      for (const Primitive& p : mesh.primitives) {
        check_bake_primitive(scene, p);
        if (p.indices.empty() || p.topology == Topology::kPoints) continue;  // trees have no points
        BakePrimitive bp;
        bp.source = &p;
        bp.mesh = &mesh;
        bp.index_count = GLsizei(p.indices.size());
        bp.blend = is_blended(scene, p);
        BakeVariant variant;
        variant.merged_lines = bp.blend && p.topology == Topology::kLines;
        variant.normals = !p.normals.empty();
        variant.colors = !p.colors.empty();
        variant.texture = p.material >= 0 &&
                          scene.materials[std::size_t(p.material)].base_color_texture >= 0 &&
                          !p.texcoords.empty();
        variant.opaque_layer = layout == BakeLayout::kLayered && !bp.blend;
        variant.lines = p.topology == Topology::kLines && !variant.merged_lines;
        bp.variant = variant.key();
        bp.vao = gl.vertex_array();
        glBindVertexArray(bp.vao);
        auto attach = [&](GLuint location, GLuint buffer, GLint comps) {
          glBindBuffer(GL_ARRAY_BUFFER, buffer);
          glEnableVertexAttribArray(location);
          glVertexAttribPointer(location, comps, GL_FLOAT, GL_FALSE, 0, nullptr);
        };
        if (bp.blend && p.topology == Topology::kLines) {
          // Coincident blended lines as one line of their composite (line_merge.h).
          const MergedLines m = merge_coincident_lines(p);
          bp.indexed = false;
          bp.index_count = GLsizei(m.positions.size());
          attach(kPosition, upload_array(gl, GL_ARRAY_BUFFER, m.positions), 3);
          if (!p.normals.empty()) {
            attach(kNormal, upload_array(gl, GL_ARRAY_BUFFER, m.normals[0]), 3);
            attach(kNormal1, upload_array(gl, GL_ARRAY_BUFFER, m.normals[1]), 3);
            attach(kNormal2, upload_array(gl, GL_ARRAY_BUFFER, m.normals[2]), 3);
          }
          if (!m.texcoords.empty()) attach(kTexcoord, upload_array(gl, GL_ARRAY_BUFFER, m.texcoords), 2);
          if (!m.colors.empty()) attach(kColor, upload_array(gl, GL_ARRAY_BUFFER, m.colors), 4);
          attach(kCopies, upload_array(gl, GL_ARRAY_BUFFER, m.copies), 1);
          glBindVertexArray(0);
          out.push_back(bp);
          continue;
        }
        attach(kPosition, upload_array(gl, GL_ARRAY_BUFFER, p.positions), 3);
        if (!p.normals.empty()) attach(kNormal, upload_array(gl, GL_ARRAY_BUFFER, p.normals), 3);
        if (!p.texcoords.empty()) attach(kTexcoord, upload_array(gl, GL_ARRAY_BUFFER, p.texcoords), 2);
        if (!p.colors.empty()) attach(kColor, upload_array(gl, GL_ARRAY_BUFFER, p.colors), 4);
        upload_array(gl, GL_ELEMENT_ARRAY_BUFFER, p.indices);
        glBindVertexArray(0);
        out.push_back(bp);
      }
    }
    // Opaque and masked first, then blended; each group in file order.
    std::stable_partition(out.begin(), out.end(), [](const BakePrimitive& p) { return !p.blend; });
    return out;
  }

  void draw_bake_row(const Scene& scene, const std::vector<BakePrimitive>& prims,
                     const std::vector<GLuint>& textures, const BakePrograms& programs,
                     const std::array<BakeUniforms, kBakeVariants>& uniforms, GLsizei count,
                     const BakeTarget& t, const BakeOptions& o) const {
    glBindFramebuffer(GL_FRAMEBUFFER, t.draw_fbo);
    glViewport(0, 0, t.width, t.height);
    glDepthMask(GL_TRUE);
    const bool layered = t.layout == BakeLayout::kLayered;
    const GLenum all[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                           GL_COLOR_ATTACHMENT3};
    if (layered) {
      // Every layer to 0 (an integer attachment is cleared by value), then the opaque pass draws
      // into the packed layer only.
      glDrawBuffers(4, all);
      const GLfloat zero[4] = {0, 0, 0, 0}, far_depth = 1;
      const GLuint zero_u[4] = {0, 0, 0, 0};
      for (GLint a = 0; a < 3; ++a) glClearBufferfv(GL_COLOR, a, zero);
      glClearBufferuiv(GL_COLOR, 3, zero_u);
      glClearBufferfv(GL_DEPTH, 0, &far_depth);
      const GLenum opaque[4] = {GL_NONE, GL_NONE, GL_NONE, GL_COLOR_ATTACHMENT3};
      glDrawBuffers(4, opaque);
    } else {
      glClearColor(0, 0, 0, 0);
      glClearDepth(1.0);
      glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glCullFace(GL_BACK);
    glDisable(GL_BLEND);
    if (o.msaa > 1)
      glEnable(GL_MULTISAMPLE);
    else
      glDisable(GL_MULTISAMPLE);
    glLineWidth(std::clamp(o.line_width_px, line_width_range_[0], line_width_range_[1]));
    bool blending = false;
    for (const BakePrimitive& bp : prims) {
      const Primitive& p = *bp.source;
      const BakeUniforms& u = uniforms[std::size_t(bp.variant)];
      glUseProgram(programs.program[std::size_t(bp.variant)]);
      if (bp.blend && !blending) {
        blending = true;
        if (layered) glDrawBuffers(3, all);  // the blended layers
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        glDepthMask(GL_FALSE);
      }
      static const Material kDefault;
      const Material& m = p.material >= 0 ? scene.materials[std::size_t(p.material)] : kDefault;
      glUniform4fv(u.base_color, 1, m.base_color.data());
      if (m.base_color_texture >= 0 && !p.texcoords.empty()) {
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, textures[std::size_t(m.base_color_texture)]);
      }
      glUniform1i(u.alpha_mode, m.alpha_mode == AlphaMode::kOpaque ? 0
                                : m.alpha_mode == AlphaMode::kMask ? 1
                                                                   : 2);
      glUniform1f(u.alpha_cutoff, m.alpha_cutoff);
      const bool triangles = p.topology == Topology::kTriangles;
      glUniform1i(u.two_sided, triangles && m.double_sided);
      glUniform1f(u.alpha_scale,
                  p.topology == Topology::kLines ? std::clamp(o.line_alpha_scale, 0.f, 1.f) : 1.f);
      if (p.normals.empty()) glVertexAttrib3f(kNormal, 0, 0, 1);
      if (p.texcoords.empty()) glVertexAttrib2f(kTexcoord, 0, 0);
      if (p.colors.empty()) glVertexAttrib4f(kColor, 1, 1, 1, 1);
      glBindVertexArray(bp.vao);
      for (const Mat4& model : bp.mesh->instances) {
        Eigen::Matrix3f n = model.topLeftCorner<3, 3>();
        const bool mirrored = n.determinant() < 0;
        if (std::abs(n.determinant()) > 1e-20f) n = n.inverse().transpose().eval();
        glUniform1i(u.mirrored, mirrored);
        // Single-sided triangles: back faces culled, as the scene renderer culls them.
        if (triangles && !m.double_sided) {
          glEnable(GL_CULL_FACE);
          glFrontFace(mirrored ? GL_CW : GL_CCW);
        } else {
          glDisable(GL_CULL_FACE);
        }
        glUniformMatrix4fv(u.model, 1, GL_FALSE, model.data());
        glUniformMatrix3fv(u.normal_matrix, 1, GL_FALSE, n.data());
        if (bp.indexed)
          glDrawElementsInstanced(gl_mode(p.topology), bp.index_count, GL_UNSIGNED_INT, nullptr, count);
        else
          glDrawArraysInstanced(gl_mode(p.topology), 0, bp.index_count, count);
      }
    }
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
  }

  // Resolves the row, reads the three attachments back into `px` (grown as needed) and writes the
  // divided values into the maps at rows [band_y, band_y + height).
  void read_bake_row(const BakeTarget& t, int band_y, RowPixels& px, BakedMaps& out) const {
    const std::size_t n = std::size_t(t.width) * std::size_t(t.height);
    if (px.color.size() < n * 4) {
      px.color.resize(n * 4);
      px.normal.resize(n * 4);
      px.depth.resize(n * 4);
    }
    const std::vector<std::uint8_t>& color = px.color;
    const std::vector<std::uint16_t>&normal = px.normal, &depth = px.depth;
    for (int a = 0; a < 3; ++a) {
      const GLenum att = GL_COLOR_ATTACHMENT0 + GLenum(a);
      if (t.resolve_fbo != t.draw_fbo) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, t.draw_fbo);
        glReadBuffer(att);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolve_fbo);
        glDrawBuffers(1, &att);
        glBlitFramebuffer(0, 0, t.width, t.height, 0, 0, t.width, t.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
      }
      glBindFramebuffer(GL_READ_FRAMEBUFFER, t.resolve_fbo);
      glReadBuffer(att);
      glPixelStorei(GL_PACK_ALIGNMENT, 1);
      if (a == 0) {
        glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_BYTE, px.color.data());
      } else {
        glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_SHORT,
                     a == 1 ? px.normal.data() : px.depth.data());
      }
    }
    if (t.resolve_fbo != t.draw_fbo) {
      const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolve_fbo);
      glDrawBuffers(3, bufs);
    }
    auto& cb = out.color.bytes();
    auto& nb = out.normal_depth.bytes();
    const std::size_t stride = std::size_t(out.color.width()) * 4;
    for (int y = 0; y < t.height; ++y) {
      const std::size_t src_row =
          std::size_t(t.height - 1 - y) * std::size_t(t.width) * 4;  // GL rows run bottom up
      const std::size_t dst_row = std::size_t(band_y + y) * stride;
      for (int x = 0; x < t.width; ++x) {
        const std::size_t s = src_row + std::size_t(x) * 4, d = dst_row + std::size_t(x) * 4;
        const int a8 = color[s + 3];
        if (a8 == 0) continue;
        // Values are coverage-weighted; the coverage is the attachments' common alpha.
        const double an = normal[s + 3] / 65535.0, ad = depth[s + 3] / 65535.0;
        for (int c = 0; c < 3; ++c)
          cb[d + c] = std::uint8_t(std::min(255, (color[s + c] * 255 + a8 / 2) / a8));
        cb[d + 3] = std::uint8_t(a8);
        // The mean of the covered samples' normals, not renormalised: its length says how much
        // they spread, and the shader lights with it (mean(n.l) = mean(n).l).
        Eigen::Vector3d nv(normal[s] / 65535.0, normal[s + 1] / 65535.0, normal[s + 2] / 65535.0);
        nv = (nv / std::max(an, 1e-9)) * 2.0 - Eigen::Vector3d::Ones();
        if (nv.norm() > 1) nv.normalize();
        for (int c = 0; c < 3; ++c)
          nb[d + c] = std::uint8_t(std::lround(std::clamp((nv[c] * 0.5 + 0.5) * 255.0, 0.0, 255.0)));
        const double dv = std::clamp(depth[s] / 65535.0 / std::max(ad, 1e-9), 0.0, 1.0);
        nb[d + 3] = std::uint8_t(std::lround(dv * 255.0));
      }
    }
  }

  // kLayered: reads the packed layer back (and the blended layers when the scene has blended
  // primitives; `px` is only ever used for one scene) into `px`, and writes the composited texels into the
  // maps at rows [band_y, band_y + height) (bake_layers.h).
  void read_layered_row(const BakeTarget& t, int band_y, bool blended, RowPixels& px, BakedMaps& out) const {
    const std::size_t n = std::size_t(t.width) * std::size_t(t.height);
    if (px.packed.size() < n * 4) {
      px.packed.resize(n * 4);
      px.color16.resize(n * 4);
      px.normal.resize(n * 4);
      px.depth.resize(n * 4);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.draw_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_COLOR_ATTACHMENT3);
    glReadPixels(0, 0, t.width, t.height, GL_RGBA_INTEGER, GL_UNSIGNED_SHORT, px.packed.data());
    if (blended) {  // else the blended layers stay as resize() made them: 0
      std::uint16_t* layers[3] = {px.color16.data(), px.normal.data(), px.depth.data()};
      for (int a = 0; a < 3; ++a) {
        glReadBuffer(GL_COLOR_ATTACHMENT0 + GLenum(a));
        glReadPixels(0, 0, t.width, t.height, GL_RGBA, GL_UNSIGNED_SHORT, layers[a]);
      }
    }
    auto& cb = out.color.bytes();
    auto& nb = out.normal_depth.bytes();
    const std::size_t stride = std::size_t(out.color.width()) * 4;
    for (int y = 0; y < t.height; ++y) {
      const std::size_t src_row = std::size_t(t.height - 1 - y) * std::size_t(t.width) * 4;  // bottom up
      const std::size_t dst_row = std::size_t(band_y + y) * stride;
      for (int x = 0; x < t.width; ++x) {
        const std::size_t s = src_row + std::size_t(x) * 4, d = dst_row + std::size_t(x) * 4;
        composite_bake_texel(&px.packed[s], &px.color16[s], &px.normal[s], &px.depth[s], &cb[d], &nb[d]);
      }
    }
  }

  struct DrawTarget {
    GLuint draw_fbo = 0, resolve_fbo = 0;
  };

  void validate_draw(const OctahedralImpostor& imp, const RenderOptions& o) const {
    if (o.width < 1 || o.height < 1 || o.width > max_size_ || o.height > max_size_)
      throw RenderError("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                        " is outside 1.." + std::to_string(max_size_));
    if (o.msaa < 1 || o.msaa > max_samples_)
      throw RenderError("msaa " + std::to_string(o.msaa) + " is not supported (this device allows 1.." +
                        std::to_string(max_samples_) + ")");
    if (o.background.a != 0 && o.background.a != 255)
      throw RenderError("background alpha must be 0 (transparent) or 255 (opaque)");
    const ImpostorGeometry& g = imp.geometry;
    const int atlas = g.frames_per_side * g.frame_px;
    if (g.frames_per_side < 2 || g.frame_px < 1 || atlas > max_texture_size_)
      throw RenderError("impostor atlas of " + std::to_string(g.frames_per_side) + " x " +
                        std::to_string(g.frame_px) +
                        " px frames is not drawable here (2 or more frames, at most " +
                        std::to_string(max_texture_size_) + " px)");
    for (const image::Image* m : {&imp.color, &imp.normal_depth})
      if (m->width() != atlas || m->height() != atlas)
        throw RenderError("impostor maps must be " + std::to_string(atlas) + "x" + std::to_string(atlas) +
                          " pixels, got " + std::to_string(m->width()) + "x" + std::to_string(m->height()));
    if (!(g.radius > 0) || !(g.half_extent >= g.radius) || g.padding_px < 0 || 2 * g.padding_px >= g.frame_px)
      throw RenderError(
          "impostor geometry is inconsistent (radius > 0, half extent >= radius, padding < frame / 2)");
  }

  DrawTarget make_draw_target(GlObjects& gl, const RenderOptions& o) const {
    auto attach = [&](GLuint fbo, GLenum attachment, GLenum format, int samples) {
      const GLuint rb = gl.renderbuffer();
      glBindRenderbuffer(GL_RENDERBUFFER, rb);
      if (samples > 1) {
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, o.width, o.height);
      } else {
        glRenderbufferStorage(GL_RENDERBUFFER, format, o.width, o.height);
      }
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, rb);
    };
    DrawTarget t;
    t.draw_fbo = gl.framebuffer();
    attach(t.draw_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, o.msaa);
    attach(t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, o.msaa);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw RenderError("cannot create the impostor target");
    t.resolve_fbo = t.draw_fbo;
    if (o.msaa > 1) {
      t.resolve_fbo = gl.framebuffer();
      attach(t.resolve_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, 1);
      if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RenderError("cannot create the impostor resolve target");
    }
    return t;
  }

  // The maps as the reference shader samples them (shaders/octahedral_impostor.frag): colour
  // rgb = sRGB(linear(rgb) * a), normal rgb = encoded normal * a, alpha and depth unchanged.
  struct PremultipliedMaps {
    image::Image color, normal_depth;
  };
  static PremultipliedMaps premultiply(const image::Image& color, const image::Image& normal_depth) {
    PremultipliedMaps out{color, normal_depth};
    premultiply_impostor_maps(out.color.bytes(), out.normal_depth.bytes());
    return out;
  }

  static GLuint upload_atlas(GlObjects& gl, const image::Image& img, bool srgb, int mip_levels) {
    const GLuint id = gl.texture();
    glBindTexture(GL_TEXTURE_2D, id);
    detail::upload_mipmapped_rgba8(img.bytes().data(), img.width(), img.height(), srgb, mip_levels);
    return id;
  }

  // Instances far to near (by the view depth of their centre; ties keep their order).
  static void sort_instances(const OctahedralImpostor& imp, const Camera& cam, GlObjects& gl, GLuint vao) {
    if (imp.instances.size() < 2) return;
    const Mat4 view = cam.view_matrix();
    std::vector<std::pair<float, std::size_t>> keys;
    for (std::size_t i = 0; i < imp.instances.size(); ++i) {
      const Vec3 w = (imp.instances[i] * imp.geometry.center.homogeneous()).hnormalized();
      keys.push_back({(view * w.homogeneous())(2), i});  // more negative = farther
    }
    std::stable_sort(keys.begin(), keys.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<float> models;
    for (const auto& k : keys)
      models.insert(models.end(), imp.instances[k.second].data(), imp.instances[k.second].data() + 16);
    glBindVertexArray(vao);
    const GLuint b = upload_array(gl, GL_ARRAY_BUFFER, models);
    for (GLuint c = 0; c < 4; ++c) {
      glVertexAttribPointer(1 + c, 4, GL_FLOAT, GL_FALSE, 16 * sizeof(float),
                            reinterpret_cast<const void*>(std::uintptr_t(c * 4 * sizeof(float))));
    }
    (void)b;
  }

  image::Image read_draw_target(const DrawTarget& t, const RenderOptions& o) const {
    if (t.resolve_fbo != t.draw_fbo) {
      glBindFramebuffer(GL_READ_FRAMEBUFFER, t.draw_fbo);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolve_fbo);
      glBlitFramebuffer(0, 0, o.width, o.height, 0, 0, o.width, o.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.resolve_fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    std::vector<std::uint8_t> raw(std::size_t(o.width) * std::size_t(o.height) * 4);
    glReadPixels(0, 0, o.width, o.height, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
    image::Image img(o.width, o.height);
    const std::size_t row = std::size_t(o.width) * 4;
    for (int y = 0; y < o.height; ++y)
      std::memcpy(&img.bytes()[std::size_t(y) * row], &raw[std::size_t(o.height - 1 - y) * row], row);
    if (o.background.a == 0) {
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

  std::unique_ptr<detail::GlContext> ctx_;
  std::vector<std::unique_ptr<Worker>> workers_;  // never destroyed before the renderer (EGL, above)
  std::mutex mutex_;
  BakePrograms bake_programs_;
  GLuint draw_program_ = 0;
  GLint max_samples_ = 1, max_size_ = 4096, max_texture_size_ = 4096;
  float line_width_range_[2] = {1.f, 1.f};
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
