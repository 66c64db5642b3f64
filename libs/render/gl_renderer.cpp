// The OpenGL 3.3 core implementation of Renderer.
//
// One shader program draws everything: uniforms select the topology (triangles, lines, points),
// the alpha mode and whether lighting applies. Every primitive is uploaded once per
// render_views() call into its own vertex buffers; the world matrices of a mesh's instances go
// into a per-instance attribute buffer (model matrix at locations 5-8, normal matrix at 9-11),
// so the opaque pass is one instanced draw per primitive. The blend pass draws each
// (primitive, instance) separately, far to near, with the matrices as constant attributes and a
// per-draw index buffer holding the elements sorted far to near. Scene::impostors are drawn
// between the two passes by impostor_draw.h (the reference impostor shader, same depth buffer;
// with hybrid antialiasing also given per pixel the farthest depth of its sub-pixels, so that the
// impostor fragments the meshes hide in every sample are not marched).
//
// Determinism: nothing depends on timing or on hash-table order; every sort is a stable sort
// with an index tie-break; llvmpipe rasterises deterministically.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>

#include "libs/render/gl_context.h"
#include "libs/render/gl_util.h"
#include "libs/render/impostor_draw.h"
#include "libs/render/renderer.h"

namespace sylva::render {
namespace {

// ---- Shaders -----------------------------------------------------------------------------------

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_texcoord;
layout(location = 3) in vec4 a_color;
layout(location = 4) in float a_size;
layout(location = 5) in mat4 a_model;
layout(location = 9) in mat3 a_normal_matrix;
layout(location = 12) in float a_copies;  // LINES: coincident copies the line stands for (Primitive::copies)

uniform mat4 u_view;
uniform mat4 u_proj;
uniform float u_viewport_height;
uniform float u_default_point_size;
uniform float u_min_point_size;

out vec3 v_world;
out vec3 v_normal;
out vec2 v_texcoord;
out vec4 v_color;
flat out float v_mirrored;  // 1 when the instance matrix mirrors (det < 0): CW is then the front
out float v_copies;

void main() {
  v_mirrored = determinant(mat3(a_model)) < 0.0 ? 1.0 : 0.0;
  vec4 world = a_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = a_normal_matrix * a_normal;
  v_texcoord = a_texcoord;
  v_color = a_color;
  v_copies = a_copies;
  gl_Position = u_proj * u_view * world;
  // Points: _SIZE is a diameter in local metres; scale it like the instance does and project
  // it (pixels = size * focal length in pixels / distance).
  if (a_size > 0.0) {
    float scale = pow(abs(determinant(mat3(a_model))), 1.0 / 3.0);
    float pixels = a_size * scale * u_proj[1][1] * 0.5 * u_viewport_height / gl_Position.w;
    gl_PointSize = max(pixels, u_min_point_size);
  } else {
    gl_PointSize = u_default_point_size;
  }
}
)";

// The fragment shader's draw state (u_has_texture ... u_round_points) is not uniforms but
// constants of one program per state (DrawState below): llvmpipe's JIT code then carries no
// branch on it. The source is kFragmentStateFormat's declarations, then kFragmentShader.
constexpr const char* kFragmentStateFormat = R"(#version 330 core
const bool u_has_texture = %s;
const int u_alpha_mode = %d;     // 0 opaque, 1 mask, 2 blend
const bool u_lit = %s;
const bool u_has_normals = %s;
const bool u_two_sided = %s;     // glTF doubleSided triangles: a back face uses the reversed normal
const bool u_cull_in_shader = %s;  // single-sided triangles of a mirrored instance: discard back faces
const bool u_round_points = %s;
const bool u_line_copies = %s;    // LINES standing for coincident copies: alpha 1 - (1 - a)^copies
)";

constexpr const char* kFragmentShader = R"(
in vec3 v_world;
in vec3 v_normal;
in vec2 v_texcoord;
in vec4 v_color;
flat in float v_mirrored;
in float v_copies;

uniform vec4 u_base_color;
uniform sampler2D u_texture;
uniform float u_alpha_cutoff;
uniform vec3 u_ambient;
uniform vec3 u_light_color;
uniform vec3 u_light_dir;     // unit, toward the light

out vec4 o_color;

float to_srgb(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

void main() {
  // glTF 2.0, 3.9.2 (double sided): the front face is the counter-clockwise one (clockwise under a
  // mirroring matrix); the back face of a double-sided material is lit with the reversed normal.
  // Nothing is inferred from the eye: a leaf wound against its normal is dark, as in clients.
  bool front = gl_FrontFacing != (v_mirrored > 0.5);
  if (u_cull_in_shader && !front) discard;
  if (u_round_points) {
    vec2 p = gl_PointCoord * 2.0 - 1.0;
    if (dot(p, p) > 1.0) discard;
  }
  vec4 base = u_base_color * v_color;
  if (u_has_texture) base *= texture(u_texture, v_texcoord);
  // What k copies of this line drawn one over the other cover, drawn once (line_merge.h).
  if (u_line_copies) base.a = 1.0 - pow(1.0 - base.a, v_copies);
  if (u_alpha_mode == 1) {
    if (base.a < u_alpha_cutoff) discard;
    base.a = 1.0;
  } else if (u_alpha_mode == 0) {
    base.a = 1.0;
  }
  vec3 color = base.rgb;
  if (u_lit) {
    // Without normals, the flat face normal (glTF: computed from the triangle) from screen-space
    // derivatives: it faces the eye, which is right for every face that is drawn (a front face,
    // or the back face of a double-sided triangle, whose reversed normal faces the eye).
    vec3 n = u_has_normals ? normalize(v_normal) : normalize(cross(dFdx(v_world), dFdy(v_world)));
    // Lines and points have no faces: their normals are used as given.
    if (u_has_normals && u_two_sided && !front) n = -n;
    color = base.rgb * (u_ambient + u_light_color * max(dot(n, u_light_dir), 0.0));
  }
  o_color = vec4(to_srgb(color.r), to_srgb(color.g), to_srgb(color.b), base.a);
}
)";

// Supersampling (RenderOptions::supersample = k): each output pixel is the mean of its k x k
// block of the k-times larger image, drawn as one full-screen triangle.
constexpr const char* kDownsampleVertexShader = R"(#version 330 core
void main() {
  vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID & 2) * 2 - 1));
  gl_Position = vec4(p, 0.0, 1.0);
}
)";

// One output pixel from the k x k texels of its block: kBlockFragmentShader after the #version
// line and the definitions of START, COMBINE(a, b) and FINISH(a).
constexpr const char* kBlockFragmentShader = R"(
uniform sampler2D u_source;
uniform int u_k;
out vec4 o_color;
void main() {
  ivec2 base = ivec2(gl_FragCoord.xy) * u_k;
  vec4 a = START;
  for (int y = 0; y < u_k; ++y)
    for (int x = 0; x < u_k; ++x) a = COMBINE(a, texelFetch(u_source, base + ivec2(x, y), 0));
  o_color = FINISH(a);
}
)";

// The mean of the block (colour).
constexpr const char* kDownsampleDefines = R"(#version 330 core
#define START vec4(0.0)
#define COMBINE(a, b) ((a) + (b))
#define FINISH(a) ((a) / float(u_k * u_k))
)";

// Hybrid antialiasing (supersample k with msaa = k^2): the sample s of a pixel of the
// multisampled target IS the sub-pixel u_sub of its k x k block in the supersampled one. To the
// multisampled target: one pass per sample (glSampleMaski), colour and depth.
constexpr const char* kToSamplesFragmentShader = R"(#version 330 core
uniform sampler2D u_color;
uniform sampler2D u_depth;
uniform int u_k;
uniform ivec2 u_sub;
out vec4 o_color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy) * u_k + u_sub;
  o_color = texelFetch(u_color, p, 0);
  gl_FragDepth = texelFetch(u_depth, p, 0).r;
}
)";

// ... and per pixel the greatest depth of its sub-pixels (into R32F, output size), for the
// impostor shader's SYLVA_SCENE_DEPTH: the block's maximum of a depth texture.
constexpr const char* kFarthestDepthDefines = R"(#version 330 core
#define START vec4(0.0)
#define COMBINE(a, b) max(a, b)
#define FINISH(a) (a)
)";

// Back to the supersampled target: colour only (the depth there is still right: impostors,
// the only pass drawn multisampled, do not write depth).
constexpr const char* kFromSamplesFragmentShader = R"(#version 330 core
uniform sampler2DMS u_samples;
uniform int u_k;
uniform int u_sample_of[16];  // sample index of sub-pixel x + k y
out vec4 o_color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 sub = p % u_k;
  o_color = texelFetch(u_samples, p / u_k, u_sample_of[sub.x + u_k * sub.y]);
}
)";

// Vertex attribute locations (see the shader).
enum : GLuint {
  kPosition = 0,
  kNormal = 1,
  kTexcoord = 2,
  kColor = 3,
  kSize = 4,
  kModel = 5,
  kNormalMatrix = 9,
  kCopies = 12
};
constexpr int kInstanceFloats = 16 + 9;

constexpr int kMaxSupersample = 4;

using detail::check_gl;
using detail::CurrentContext;
using detail::gl_mode;
using detail::GlObjects;
using detail::upload_array;
using detail::upload_texture;

// ---- Uploaded scene ----------------------------------------------------------------------------

struct GpuPrimitive {
  const Primitive* source = nullptr;
  GLuint vao_instanced = 0;  // vertex arrays + per-instance matrices
  GLuint vao_single = 0;     // vertex arrays (elements from Uploaded::blend_indices); matrices as constants
  GLsizei index_count = 0;
  bool blend = false;
};

struct GpuMesh {
  const Mesh* source = nullptr;
  std::vector<GpuPrimitive> primitives;
  std::vector<float> instance_data;  // kInstanceFloats per instance
  bool mirrored = false;             // some instance matrix has a negative determinant
};

// Binds the vertex arrays of `p` (the buffers already exist) into the bound VAO.
struct VertexBuffers {
  GLuint position = 0, normal = 0, texcoord = 0, color = 0, size = 0, copies = 0;
};

void attach_vertex_buffers(const VertexBuffers& vb) {
  auto attach = [](GLuint location, GLuint buffer, GLint comps) {
    if (!buffer) return;
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glEnableVertexAttribArray(location);
    glVertexAttribPointer(location, comps, GL_FLOAT, GL_FALSE, 0, nullptr);
  };
  attach(kPosition, vb.position, 3);
  attach(kNormal, vb.normal, 3);
  attach(kTexcoord, vb.texcoord, 2);
  attach(kColor, vb.color, 4);
  attach(kSize, vb.size, 1);
  attach(kCopies, vb.copies, 1);
}

void fill_instance(const Mat4& m, float* out) {
  std::memcpy(out, m.data(), 16 * sizeof(float));
  Eigen::Matrix3f n = m.topLeftCorner<3, 3>();
  const float det = n.determinant();
  if (std::abs(det) > 1e-20f) n = n.inverse().transpose().eval();
  std::memcpy(out + 16, n.data(), 9 * sizeof(float));
}

// ---- The renderer ------------------------------------------------------------------------------

class GlRenderer final : public Renderer {
 public:
  explicit GlRenderer(std::unique_ptr<detail::GlContext> ctx) : ctx_(std::move(ctx)) {
    CurrentContext current(*ctx_);
    downsample_ =
        detail::link_program(kDownsampleVertexShader,
                             (std::string(kDownsampleDefines) + kBlockFragmentShader).c_str(), "downsample");
    to_samples_ = detail::link_program(kDownsampleVertexShader, kToSamplesFragmentShader, "to samples");
    farthest_depth_ = detail::link_program(
        kDownsampleVertexShader, (std::string(kFarthestDepthDefines) + kBlockFragmentShader).c_str(),
        "farthest depth");
    from_samples_ = detail::link_program(kDownsampleVertexShader, kFromSamplesFragmentShader, "from samples");
    glGetIntegerv(GL_MAX_SAMPLES, &max_samples_);
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size_);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture_size_);
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, line_width_range_);
    check_gl("initialisation");
  }

  ~GlRenderer() override {
    try {
      CurrentContext current(*ctx_);
      for (const auto& [key, program] : programs_) glDeleteProgram(program.id);
      for (const KeptGeometry& k : kept_geometry_)
        glDeleteBuffers(GLsizei(k.buffers.size()), k.buffers.data());
      kept_target_.gl.reset();
      glDeleteProgram(downsample_);
      glDeleteProgram(to_samples_);
      glDeleteProgram(farthest_depth_);
      glDeleteProgram(from_samples_);
      impostors_.destroy();
    } catch (...) {
      // The context is going away with us; nothing else to release.
    }
  }

  std::string device_description() const override { return ctx_->description(); }

  std::size_t kept_geometry() const override { return kept_geometry_.size(); }
  std::size_t kept_impostor_atlases() const override { return impostors_.kept(); }

  void prepare(const Scene& scene, const RenderOptions& options) override {
    std::lock_guard<std::mutex> lock(mutex_);
    CurrentContext current(*ctx_);
    validate(options);
    GlObjects gl;  // the impostor drawer's per-call objects; the kept ones outlive it
    glGetError();
    target_for(options);
    drop_dead_geometry();
    for (const Mesh& mesh : scene.meshes) {
      if (!mesh.shared_geometry) continue;
      for (const Primitive& p : mesh.primitives) check_primitive(scene, p);
      kept_buffers(scene, mesh);
    }
    impostors_.upload(gl, scene.impostors, max_texture_size_,
                      hybrid(options) && options.impostor_hidden_discard);
    check_gl("upload");
  }

  std::vector<image::Image> render_views(const Scene& scene, std::span<const Camera> cameras,
                                         const RenderOptions& options) override {
    std::lock_guard<std::mutex> lock(mutex_);
    CurrentContext current(*ctx_);
    validate(options);
    GlObjects gl;
    glGetError();  // start from a clean error state
    const Target& target = target_for(options);
    const Uploaded up = upload(gl, scene);
    const detail::ImpostorDrawer::Uploaded imp = impostors_.upload(
        gl, scene.impostors, max_texture_size_, hybrid(options) && options.impostor_hidden_discard);
    check_gl("upload");
    std::vector<image::Image> images;
    images.reserve(cameras.size());
    for (const Camera& cam : cameras) {
      draw(scene, up, imp, cam, options, target);
      images.push_back(read_back(target, options));
      check_gl("drawing");
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return images;
  }

 private:
  // Where a view is drawn. Without supersampling: draw_fbo (msaa samples), resolved into
  // resolve_fbo. Supersampled by k: draw_fbo is k times the size, one sample per pixel, averaged
  // into output_fbo; with msaa = k^2 as well ("hybrid"), impostors are drawn into samples_fbo,
  // whose k^2 samples per pixel are the k x k sub-pixels of draw_fbo (sample_of).
  struct Target {
    int width = 0, height = 0;    // of draw_fbo: k x the output's
    GLuint draw_fbo = 0;          // multisampled when msaa > 1 and not supersampled
    GLuint resolve_fbo = 0;       // single-sampled; == draw_fbo when msaa == 1 or supersampled
    GLuint color_texture = 0;     // draw_fbo's colour when supersampled
    GLuint depth_texture = 0;     // draw_fbo's depth when hybrid
    GLuint output_fbo = 0;        // the output size; == resolve_fbo when not supersampled
    GLuint samples_fbo = 0;       // hybrid: output size, k^2 samples
    GLuint samples_texture = 0;   // its colour
    GLuint farthest_fbo = 0;      // hybrid: output size, R32F colour farthest_texture:
    GLuint farthest_texture = 0;  // per pixel the greatest depth of its sub-pixels
    std::vector<int> sample_of;   // hybrid: sample index of sub-pixel x + k y
    GLuint empty_vao = 0;         // for the full-screen passes
  };

  struct Uploaded {
    std::vector<GLuint> textures;
    std::vector<GpuMesh> meshes;
    GLuint blend_indices = 0;  // every blended draw's sorted elements of one view (0: no BLEND primitive)
  };

  // A primitive's vertex arrays and, unless it is blended, its element buffer.
  struct PrimitiveBuffers {
    VertexBuffers vb;
    GLuint elements = 0;
    std::size_t vertices = 0, indices = 0;  // the counts uploaded
  };

  // The buffers of a Mesh::shared_geometry, kept between calls while the geometry's name lives
  // (checked at every upload, as the impostor maps are) or until the renderer is destroyed.
  struct KeptGeometry {
    std::weak_ptr<const void> owner;
    const void* key = nullptr;
    std::vector<PrimitiveBuffers> primitives;
    std::vector<GLuint> buffers;  // every name in `primitives`
  };

  // The target of the last call, kept for the next one of the same size and sampling.
  struct KeptTarget {
    std::unique_ptr<GlObjects> gl;
    Target target;
    int width = 0, height = 0, msaa = 0, supersample = 0;
  };

  void validate(const RenderOptions& o) const {
    if (o.supersample < 1 || o.supersample > kMaxSupersample)
      throw RenderError("supersample " + std::to_string(o.supersample) + " is not supported (1.." +
                        std::to_string(kMaxSupersample) + ")");
    const int k = o.supersample;
    if (o.width < 1 || o.height < 1 || o.width > max_size_ / k || o.height > max_size_ / k)
      throw RenderError("image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                        (k > 1 ? " supersampled " + std::to_string(k) + "x" : std::string()) +
                        " is outside 1.." + std::to_string(max_size_));
    if (o.msaa < 1 || o.msaa > max_samples_)
      throw RenderError("msaa " + std::to_string(o.msaa) + " is not supported (this device allows 1.." +
                        std::to_string(max_samples_) + ")");
    if (k > 1 && o.msaa > 1 && o.msaa != k * k)
      throw RenderError("supersample " + std::to_string(k) + " needs msaa 1 or " + std::to_string(k * k) +
                        " (the samples of a pixel are its sub-pixels), got msaa " + std::to_string(o.msaa));
    if (o.background.a != 0 && o.background.a != 255)
      throw RenderError("background alpha must be 0 (transparent) or 255 (opaque)");
    if (!(o.line_width_px > 0) || !(o.default_point_size_px > 0) || !(o.min_point_size_px > 0))
      throw RenderError("line width and point sizes must be positive");
  }

  static bool hybrid(const RenderOptions& o) { return o.supersample > 1 && o.msaa > 1; }

  Target make_target(GlObjects& gl, const RenderOptions& o) const {
    Target t;
    const int k = o.supersample;
    t.width = o.width * k;
    t.height = o.height * k;
    auto renderbuffer = [&](GLuint fbo, GLenum attachment, GLenum format, int samples, int w, int h) {
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
    auto texture = [&](GLuint fbo, GLenum attachment, GLenum internal, GLenum format, GLenum type) {
      const GLuint tex = gl.texture();
      glBindTexture(GL_TEXTURE_2D, tex);
      glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal), t.width, t.height, 0, format, type, nullptr);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_2D, tex, 0);
      return tex;
    };
    auto complete = [&](const std::string& what) {
      if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RenderError("cannot create " + what);
    };
    t.draw_fbo = gl.framebuffer();
    if (k == 1) {
      renderbuffer(t.draw_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, o.msaa, t.width, t.height);
      renderbuffer(t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, o.msaa, t.width, t.height);
      complete("a " + std::to_string(t.width) + "x" + std::to_string(t.height) + " framebuffer");
      t.resolve_fbo = t.output_fbo = t.draw_fbo;
      if (o.msaa > 1) {
        t.resolve_fbo = t.output_fbo = gl.framebuffer();
        renderbuffer(t.resolve_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, 1, t.width, t.height);
        complete("the resolve framebuffer");
      }
      return t;
    }
    t.color_texture = texture(t.draw_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE);
    if (hybrid(o)) {
      t.depth_texture =
          texture(t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT);
    } else {
      renderbuffer(t.draw_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, 1, t.width, t.height);
    }
    complete("a " + std::to_string(t.width) + "x" + std::to_string(t.height) + " framebuffer");
    t.resolve_fbo = t.draw_fbo;
    t.output_fbo = gl.framebuffer();
    renderbuffer(t.output_fbo, GL_COLOR_ATTACHMENT0, GL_RGBA8, 1, o.width, o.height);
    complete("the downsampling framebuffer");
    t.empty_vao = gl.vertex_array();
    if (hybrid(o)) {
      t.samples_fbo = gl.framebuffer();
      t.samples_texture = gl.texture();
      glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, t.samples_texture);
      glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, o.msaa, GL_RGBA8, o.width, o.height, GL_TRUE);
      glBindFramebuffer(GL_FRAMEBUFFER, t.samples_fbo);
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE,
                             t.samples_texture, 0);
      renderbuffer(t.samples_fbo, GL_DEPTH_ATTACHMENT, GL_DEPTH_COMPONENT32F, o.msaa, o.width, o.height);
      complete("the multisampled framebuffer");
      // Each sample stands for the sub-pixel its position falls in (the device's pattern has
      // one sample per k x k cell, as the standard 4-sample pattern does for k = 2); else by index.
      t.sample_of.assign(std::size_t(k * k), -1);
      bool bijective = true;
      for (int s = 0; s < o.msaa; ++s) {
        GLfloat pos[2] = {0.5f, 0.5f};
        glGetMultisamplefv(GL_SAMPLE_POSITION, GLuint(s), pos);
        const int sx = std::clamp(int(pos[0] * float(k)), 0, k - 1),
                  sy = std::clamp(int(pos[1] * float(k)), 0, k - 1);
        int& slot = t.sample_of[std::size_t(sx + k * sy)];
        bijective = bijective && slot < 0;
        slot = s;
      }
      if (!bijective)
        for (int s = 0; s < o.msaa; ++s) t.sample_of[std::size_t(s)] = s;
      t.farthest_fbo = gl.framebuffer();
      t.farthest_texture = gl.texture();
      glBindTexture(GL_TEXTURE_2D, t.farthest_texture);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, o.width, o.height, 0, GL_RED, GL_FLOAT, nullptr);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
      glBindFramebuffer(GL_FRAMEBUFFER, t.farthest_fbo);
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t.farthest_texture, 0);
      complete("the farthest-depth framebuffer");
    }
    return t;
  }

  // The target for `o`, kept between calls while the size, samples and supersampling stay the
  // same (every pass of a view overwrites all of it).
  const Target& target_for(const RenderOptions& o) {
    KeptTarget& k = kept_target_;
    if (!k.gl || k.width != o.width || k.height != o.height || k.msaa != o.msaa ||
        k.supersample != o.supersample) {
      k.gl.reset();
      auto gl = std::make_unique<GlObjects>();
      k.target = make_target(*gl, o);
      k.gl = std::move(gl);
      k.width = o.width;
      k.height = o.height;
      k.msaa = o.msaa;
      k.supersample = o.supersample;
    }
    return k.target;
  }

  // A primitive's vertex arrays and, unless it is blended, its element buffer, in buffers named
  // by `new_buffer()`.
  template <typename NewBuffer>
  static PrimitiveBuffers upload_buffers(const Primitive& p, bool blend, NewBuffer&& new_buffer) {
    auto array = [&](GLenum target, const auto& data) {
      const GLuint name = new_buffer();
      glBindBuffer(target, name);
      glBufferData(target, GLsizeiptr(data.size() * sizeof(data[0])), data.data(), GL_STATIC_DRAW);
      return name;
    };
    glBindVertexArray(0);
    PrimitiveBuffers b;
    b.vertices = p.positions.size();
    b.indices = p.indices.size();
    b.vb.position = array(GL_ARRAY_BUFFER, p.positions);
    if (!p.normals.empty()) b.vb.normal = array(GL_ARRAY_BUFFER, p.normals);
    if (!p.texcoords.empty()) b.vb.texcoord = array(GL_ARRAY_BUFFER, p.texcoords);
    if (!p.colors.empty()) b.vb.color = array(GL_ARRAY_BUFFER, p.colors);
    if (!p.sizes.empty() && p.topology == Topology::kPoints) b.vb.size = array(GL_ARRAY_BUFFER, p.sizes);
    if (!p.copies.empty() && p.topology == Topology::kLines) b.vb.copies = array(GL_ARRAY_BUFFER, p.copies);
    if (!blend) b.elements = array(GL_ELEMENT_ARRAY_BUFFER, p.indices);
    return b;
  }

  // The buffers of a mesh naming shared geometry: kept from an earlier call when its name still
  // lives and its primitives have the vertex and index counts kept, else uploaded and kept.
  const std::vector<PrimitiveBuffers>& kept_buffers(const Scene& scene, const Mesh& mesh) {
    auto same = [&](const KeptGeometry& k) {
      if (k.key != mesh.shared_geometry.get()) return false;
      const std::shared_ptr<const void> alive = k.owner.lock();
      return alive && !alive.owner_before(mesh.shared_geometry) && !mesh.shared_geometry.owner_before(alive);
    };
    auto it = std::find_if(kept_geometry_.begin(), kept_geometry_.end(), same);
    if (it != kept_geometry_.end()) {
      bool fits = it->primitives.size() == mesh.primitives.size();
      for (std::size_t i = 0; fits && i < mesh.primitives.size(); ++i)
        fits = it->primitives[i].vertices == mesh.primitives[i].positions.size() &&
               it->primitives[i].indices == mesh.primitives[i].indices.size();
      if (fits) return it->primitives;
      glDeleteBuffers(GLsizei(it->buffers.size()), it->buffers.data());
      kept_geometry_.erase(it);
    }
    KeptGeometry k;
    k.owner = mesh.shared_geometry;
    k.key = mesh.shared_geometry.get();
    auto new_buffer = [&] {
      GLuint name = 0;
      glGenBuffers(1, &name);
      k.buffers.push_back(name);
      return name;
    };
    for (const Primitive& p : mesh.primitives)
      k.primitives.push_back(upload_buffers(p, blended(scene, p), new_buffer));
    // Buffers that did not upload (out of memory) are not kept: the next call tries again.
    if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
      glDeleteBuffers(GLsizei(k.buffers.size()), k.buffers.data());
      throw RenderError("mesh '" + mesh.name + "' could not be uploaded (GL error " + std::to_string(e) +
                        ")");
    }
    kept_geometry_.push_back(std::move(k));
    return kept_geometry_.back().primitives;
  }

  static bool blended(const Scene& scene, const Primitive& p) {
    return p.material >= 0 && scene.materials[std::size_t(p.material)].alpha_mode == AlphaMode::kBlend;
  }

  // Kept geometry whose name no longer lives is deleted first at every call (whatever it draws).
  void drop_dead_geometry() {
    std::erase_if(kept_geometry_, [](const KeptGeometry& k) {
      if (!k.owner.expired()) return false;
      glDeleteBuffers(GLsizei(k.buffers.size()), k.buffers.data());
      return true;
    });
  }

  Uploaded upload(GlObjects& gl, const Scene& scene) {
    drop_dead_geometry();
    Uploaded up;
    for (const Texture& t : scene.textures) up.textures.push_back(upload_texture(gl, t));
    for (const Mesh& mesh : scene.meshes) {
      GpuMesh gm;
      gm.source = &mesh;
      if (mesh.instances.empty()) {
        up.meshes.push_back(std::move(gm));
        continue;
      }
      gm.instance_data.resize(mesh.instances.size() * kInstanceFloats);
      for (std::size_t i = 0; i < mesh.instances.size(); ++i) {
        fill_instance(mesh.instances[i], &gm.instance_data[i * kInstanceFloats]);
        gm.mirrored |= mesh.instances[i].topLeftCorner<3, 3>().determinant() < 0;
      }
      const GLuint instance_buffer = upload_array(gl, GL_ARRAY_BUFFER, gm.instance_data);
      for (const Primitive& p : mesh.primitives) check_primitive(scene, p);
      std::vector<PrimitiveBuffers> own;
      if (!mesh.shared_geometry)
        for (const Primitive& p : mesh.primitives)
          own.push_back(upload_buffers(p, blended(scene, p), [&] { return gl.buffer(); }));
      const std::vector<PrimitiveBuffers>& buffers = mesh.shared_geometry ? kept_buffers(scene, mesh) : own;
      for (std::size_t i = 0; i < mesh.primitives.size(); ++i) {
        const Primitive& p = mesh.primitives[i];
        const PrimitiveBuffers& b = buffers[i];
        GpuPrimitive gp;
        gp.source = &p;
        gp.index_count = GLsizei(p.indices.size());
        gp.blend = blended(scene, p);
        if (!gp.blend) {
          gp.vao_instanced = gl.vertex_array();
          glBindVertexArray(gp.vao_instanced);
          attach_vertex_buffers(b.vb);
          glBindBuffer(GL_ARRAY_BUFFER, instance_buffer);
          const GLsizei stride = kInstanceFloats * sizeof(float);
          for (GLuint c = 0; c < 4; ++c) {
            glEnableVertexAttribArray(kModel + c);
            glVertexAttribPointer(kModel + c, 4, GL_FLOAT, GL_FALSE, stride,
                                  reinterpret_cast<const void*>(std::uintptr_t(c * 4 * sizeof(float))));
            glVertexAttribDivisor(kModel + c, 1);
          }
          for (GLuint c = 0; c < 3; ++c) {
            glEnableVertexAttribArray(kNormalMatrix + c);
            glVertexAttribPointer(
                kNormalMatrix + c, 3, GL_FLOAT, GL_FALSE, stride,
                reinterpret_cast<const void*>(std::uintptr_t((16 + c * 3) * sizeof(float))));
            glVertexAttribDivisor(kNormalMatrix + c, 1);
          }
          glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.elements);
        } else {
          gp.vao_single = gl.vertex_array();
          glBindVertexArray(gp.vao_single);
          attach_vertex_buffers(b.vb);
          if (!up.blend_indices) up.blend_indices = gl.buffer();
        }
        glBindVertexArray(0);
        gm.primitives.push_back(gp);
      }
      up.meshes.push_back(std::move(gm));
    }
    return up;
  }

  // The GL side trusts these; load_gltf_scene guarantees them, hand-built scenes are checked.
  static void check_primitive(const Scene& scene, const Primitive& p) {
    const std::size_t n = p.positions.size();
    auto bad = [&](const std::string& what) {
      throw RenderError("invalid primitive in scene '" + scene.source + "': " + what);
    };
    if ((!p.normals.empty() && p.normals.size() != n) || (!p.texcoords.empty() && p.texcoords.size() != n) ||
        (!p.colors.empty() && p.colors.size() != n) || (!p.sizes.empty() && p.sizes.size() != n) ||
        (!p.copies.empty() && p.copies.size() != n))
      bad("attribute arrays differ in length from positions");
    for (std::uint32_t i : p.indices)
      if (i >= n) bad("index " + std::to_string(i) + " out of range");
    if (p.material >= 0 && std::size_t(p.material) >= scene.materials.size()) bad("material out of range");
    if (p.material >= 0) {
      const int t = scene.materials[std::size_t(p.material)].base_color_texture;
      if (t >= 0 && std::size_t(t) >= scene.textures.size()) bad("texture out of range");
    }
  }

  struct Uniforms {
    GLint view, proj, viewport_height, default_point_size, min_point_size, base_color, texture, alpha_cutoff,
        ambient, light_color, light_dir;
  };

  static Uniforms uniforms(GLuint program) {
    auto u = [&](const char* n) { return glGetUniformLocation(program, n); };
    return {u("u_view"),           u("u_proj"),        u("u_viewport_height"), u("u_default_point_size"),
            u("u_min_point_size"), u("u_base_color"),  u("u_texture"),         u("u_alpha_cutoff"),
            u("u_ambient"),        u("u_light_color"), u("u_light_dir")};
  }

  // What a draw's fragment shader is specialised for (kFragmentStateFormat).
  struct DrawState {
    bool textured = false;
    int alpha_mode = 0;  // 0 opaque, 1 mask, 2 blend
    bool lit = false, has_normals = false, two_sided = false, cull_in_shader = false, round_points = false;
    bool line_copies = false;
    int key() const {
      return int(textured) | alpha_mode << 1 | int(lit) << 3 | int(has_normals) << 4 | int(two_sided) << 5 |
             int(cull_in_shader) << 6 | int(round_points) << 7 | int(line_copies) << 8;
    }
  };

  // One linked program per DrawState used so far, and which view's uniforms it holds.
  struct Program {
    GLuint id = 0;
    Uniforms u{};
    std::uint64_t view = 0;
  };

  // The uniforms every program of one view shares.
  struct ViewUniforms {
    Mat4 view = Mat4::Identity(), proj = Mat4::Identity();
    float viewport_height = 0, default_point_size = 0, min_point_size = 0;
    Vec3 ambient = Vec3::Zero(), light_color = Vec3::Zero(), light_dir = Vec3::UnitY();
  };

  // Makes the program for `st` current (linking it on first use) with this view's uniforms.
  const Program& use_program(const DrawState& st) {
    auto it = programs_.find(st.key());
    if (it == programs_.end()) {
      auto b = [](bool v) { return v ? "true" : "false"; };
      char head[640];
      std::snprintf(head, sizeof head, kFragmentStateFormat, b(st.textured), st.alpha_mode, b(st.lit),
                    b(st.has_normals), b(st.two_sided), b(st.cull_in_shader), b(st.round_points),
                    b(st.line_copies));
      Program p;
      p.id = detail::link_program(kVertexShader, (std::string(head) + kFragmentShader).c_str(), "scene");
      p.u = uniforms(p.id);
      it = programs_.emplace(st.key(), p).first;
    }
    Program& p = it->second;
    if (current_program_ != p.id) {
      glUseProgram(p.id);
      current_program_ = p.id;
    }
    if (p.view != view_serial_) {
      const ViewUniforms& v = view_uniforms_;
      glUniformMatrix4fv(p.u.view, 1, GL_FALSE, v.view.data());
      glUniformMatrix4fv(p.u.proj, 1, GL_FALSE, v.proj.data());
      glUniform1f(p.u.viewport_height, v.viewport_height);
      glUniform1f(p.u.default_point_size, v.default_point_size);
      glUniform1f(p.u.min_point_size, v.min_point_size);
      glUniform1i(p.u.texture, 0);
      glUniform3fv(p.u.ambient, 1, v.ambient.data());
      glUniform3fv(p.u.light_color, 1, v.light_color.data());
      glUniform3fv(p.u.light_dir, 1, v.light_dir.data());
      p.view = view_serial_;
    }
    return p;
  }

  // Material and per-primitive state for one draw.
  void set_primitive_state(const Scene& scene, const Uploaded& up, const Primitive& p,
                           bool mirrored_instances) {
    static const Material kDefault;
    const Material& m = p.material >= 0 ? scene.materials[std::size_t(p.material)] : kDefault;
    DrawState st;
    st.textured = m.base_color_texture >= 0 && !p.texcoords.empty();
    st.alpha_mode = m.alpha_mode == AlphaMode::kOpaque ? 0 : m.alpha_mode == AlphaMode::kMask ? 1 : 2;
    st.has_normals = !p.normals.empty();
    // LINES are unlit, as three.js draws them (GLTFLoader: LineBasicMaterial = base colour x
    // COLOR_0): glTF defines no lighting for lines, and the verifier must see what clients do.
    st.lit =
        !m.unlit && p.topology != Topology::kLines && (p.topology == Topology::kTriangles || st.has_normals);
    const bool triangles = p.topology == Topology::kTriangles;
    st.two_sided = triangles && m.double_sided;
    st.round_points = p.topology == Topology::kPoints;
    st.line_copies = p.topology == Topology::kLines && !p.copies.empty();
    // Back faces of single-sided triangles are culled; GL's cull state is per draw, so a mesh
    // with a mirrored instance culls in the shader instead (front = CW there).
    const bool cull = triangles && !m.double_sided;
    st.cull_in_shader = cull && mirrored_instances;
    const Program& program = use_program(st);
    glUniform4fv(program.u.base_color, 1, m.base_color.data());
    glUniform1f(program.u.alpha_cutoff, m.alpha_cutoff);
    if (st.textured) {
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, up.textures[std::size_t(m.base_color_texture)]);
    }
    if (cull && !mirrored_instances) {
      glEnable(GL_CULL_FACE);
    } else {
      glDisable(GL_CULL_FACE);
    }
    // Constant values for the attributes this primitive does not have.
    if (p.normals.empty()) glVertexAttrib3f(kNormal, 0, 0, 1);
    if (p.texcoords.empty()) glVertexAttrib2f(kTexcoord, 0, 0);
    if (p.colors.empty()) glVertexAttrib4f(kColor, 1, 1, 1, 1);
    if (p.sizes.empty() || p.topology != Topology::kPoints) glVertexAttrib1f(kSize, -1.f);
    if (!st.line_copies) glVertexAttrib1f(kCopies, 1.f);
  }

  void draw(const Scene& scene, const Uploaded& up, const detail::ImpostorDrawer::Uploaded& imp,
            const Camera& cam, const RenderOptions& o, const Target& t) {
    glBindFramebuffer(GL_FRAMEBUFFER, t.draw_fbo);
    glViewport(0, 0, t.width, t.height);
    // Supersampled, lines and points keep their width in output pixels: k drawn pixels.
    const float k = float(o.supersample);
    const bool transparent = o.background.a == 0;
    glClearColor(transparent ? 0.f : o.background.r / 255.f, transparent ? 0.f : o.background.g / 255.f,
                 transparent ? 0.f : o.background.b / 255.f, o.background.a / 255.f);
    glClearDepth(1.0);
    glDepthMask(GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    glDisable(GL_BLEND);
    glEnable(GL_PROGRAM_POINT_SIZE);
    if (o.msaa > 1 && o.supersample == 1) {
      glEnable(GL_MULTISAMPLE);
    } else {
      glDisable(GL_MULTISAMPLE);
    }
    glLineWidth(std::clamp(o.line_width_px * k, line_width_range_[0], line_width_range_[1]));

    const float aspect = float(o.width) / float(o.height);
    const Mat4 view = cam.view_matrix();
    const Mat4 proj = cam.projection_matrix(aspect);
    view_uniforms_ = {view,
                      proj,
                      float(t.height),
                      o.default_point_size_px * k,
                      o.min_point_size_px * k,
                      o.lighting.ambient,
                      o.lighting.light_color,
                      o.lighting.direction_to_light.norm() > 0
                          ? Vec3(o.lighting.direction_to_light.normalized())
                          : Vec3::UnitY()};
    ++view_serial_;
    current_program_ = 0;

    // Pass 1: opaque and masked, one instanced draw per primitive.
    struct BlendDraw {
      const GpuPrimitive* prim;
      const GpuMesh* mesh;
      std::size_t instance;
      float depth;  // view-space distance along the viewing direction
      std::size_t order;
    };
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
        set_primitive_state(scene, up, *gp.source, gm.mirrored);
        glBindVertexArray(gp.vao_instanced);
        glDrawElementsInstanced(gl_mode(gp.source->topology), gp.index_count, GL_UNSIGNED_INT, nullptr,
                                GLsizei(instances));
      }
    }

    // Impostors: behind what pass 1 drew where it is nearer, blended over it elsewhere.
    if (!scene.impostors.empty()) {
      if (hybrid(o)) {
        if (o.impostor_hidden_discard) farthest_depth(t, o);
        to_samples(t, o);
        impostors_.draw(scene.impostors, imp, cam, aspect, o.lighting,
                        o.impostor_hidden_discard ? t.farthest_texture : 0);
        from_samples(t, o);
      } else {
        impostors_.draw(scene.impostors, imp, cam, aspect, o.lighting);
      }
      current_program_ = 0;  // the impostor drawer used its own
    }

    // Pass 2: blended, far to near (Zhang et al. 2017, 6.1), depth test on, depth write off.
    // Every draw's sorted elements go into one index buffer, uploaded once before the first
    // draw: rewriting one buffer per draw would make the driver finish every earlier draw that
    // reads it first (llvmpipe: a full flush and wait per blended instance).
    if (!blended.empty()) {
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
        set_primitive_state(scene, up, p, d.mesh->mirrored);
        glBindVertexArray(d.prim->vao_single);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, up.blend_indices);
        const float* inst = &d.mesh->instance_data[d.instance * kInstanceFloats];
        for (GLuint c = 0; c < 4; ++c) glVertexAttrib4fv(kModel + c, inst + c * 4);
        for (GLuint c = 0; c < 3; ++c) glVertexAttrib3fv(kNormalMatrix + c, inst + 16 + c * 3);
        glDrawElements(gl_mode(p.topology), d.prim->index_count, GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(std::uintptr_t(offset[i] * sizeof(std::uint32_t))));
      }
      glDepthMask(GL_TRUE);
      glDisable(GL_BLEND);
    }
    glBindVertexArray(0);
  }

  // One full-screen triangle at the output size into `fbo` with `program` (kBlockFragmentShader)
  // reading `texture`: the downsample and the farthest-depth passes. Leaves depth test, blending,
  // culling and multisampling off.
  void output_pass(const Target& t, const RenderOptions& o, GLuint fbo, GLuint program,
                   GLuint texture) const {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, o.width, o.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_MULTISAMPLE);
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "u_source"), 0);
    glUniform1i(glGetUniformLocation(program, "u_k"), o.supersample);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, texture);
    glBindVertexArray(t.empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
  }

  // Hybrid antialiasing: per output pixel the greatest depth of its sub-pixels, into
  // farthest_texture (the impostor shader's SYLVA_SCENE_DEPTH).
  void farthest_depth(const Target& t, const RenderOptions& o) const {
    output_pass(t, o, t.farthest_fbo, farthest_depth_, t.depth_texture);
  }

  // Hybrid antialiasing: the supersampled colour and depth into the multisampled target (sample
  // s of a pixel = its sub-pixel), ready for the impostors; bound, with its viewport.
  void to_samples(const Target& t, const RenderOptions& o) const {
    const int k = o.supersample;
    glBindFramebuffer(GL_FRAMEBUFFER, t.samples_fbo);
    glViewport(0, 0, o.width, o.height);
    glEnable(GL_MULTISAMPLE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(to_samples_);
    glUniform1i(glGetUniformLocation(to_samples_, "u_color"), 0);
    glUniform1i(glGetUniformLocation(to_samples_, "u_depth"), 1);
    glUniform1i(glGetUniformLocation(to_samples_, "u_k"), k);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, t.color_texture);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, t.depth_texture);
    glActiveTexture(GL_TEXTURE0);
    glBindVertexArray(t.empty_vao);
    glEnable(GL_SAMPLE_MASK);
    const GLint sub = glGetUniformLocation(to_samples_, "u_sub");
    for (int i = 0; i < k * k; ++i) {
      glSampleMaski(0, 1u << unsigned(t.sample_of[std::size_t(i)]));
      glUniform2i(sub, i % k, i / k);
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    glDisable(GL_SAMPLE_MASK);
    glBindVertexArray(0);
    glDepthFunc(GL_LESS);
  }

  // ... and the samples' colour back into the supersampled target (its depth is unchanged:
  // impostors do not write depth); draw_fbo bound again with its viewport and depth test.
  void from_samples(const Target& t, const RenderOptions& o) const {
    const int k = o.supersample;
    glBindFramebuffer(GL_FRAMEBUFFER, t.draw_fbo);
    glViewport(0, 0, t.width, t.height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(from_samples_);
    glUniform1i(glGetUniformLocation(from_samples_, "u_samples"), 0);
    glUniform1i(glGetUniformLocation(from_samples_, "u_k"), k);
    glUniform1iv(glGetUniformLocation(from_samples_, "u_sample_of"), GLsizei(t.sample_of.size()),
                 t.sample_of.data());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, t.samples_texture);
    glBindVertexArray(t.empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, 0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
  }

  // The primitive's elements ordered far to near (view depth of their centroid; ties keep file
  // order), written as an index list into `out`.
  static void sort_elements(const Primitive& p, const Mat4& model_view,
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
    std::stable_sort(keys.begin(), keys.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    for (std::size_t e = 0; e < n; ++e)
      for (std::size_t k = 0; k < per; ++k)
        out[e * per + k] = p.indices[std::size_t(keys[e].second) * per + k];
  }

  image::Image read_back(const Target& t, const RenderOptions& o) const {
    if (t.resolve_fbo != t.draw_fbo) {
      glBindFramebuffer(GL_READ_FRAMEBUFFER, t.draw_fbo);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t.resolve_fbo);
      glBlitFramebuffer(0, 0, t.width, t.height, 0, 0, t.width, t.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    if (t.output_fbo != t.resolve_fbo) {
      output_pass(t, o, t.output_fbo, downsample_, t.color_texture);
      glEnable(GL_DEPTH_TEST);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t.output_fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    std::vector<std::uint8_t> raw(std::size_t(o.width) * std::size_t(o.height) * 4);
    glReadPixels(0, 0, o.width, o.height, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
    image::Image img(o.width, o.height);
    const std::size_t row = std::size_t(o.width) * 4;
    for (int y = 0; y < o.height; ++y)  // GL's first row is the bottom one
      std::memcpy(&img.bytes()[std::size_t(y) * row], &raw[std::size_t(o.height - 1 - y) * row], row);
    if (o.background.a == 0) {
      // Over a transparent background the framebuffer holds premultiplied colour.
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
  std::mutex mutex_;
  std::vector<KeptGeometry> kept_geometry_;
  KeptTarget kept_target_;
  std::map<int, Program> programs_;  // by DrawState::key()
  GLuint current_program_ = 0;       // within draw(): the program in use, 0 = unknown
  ViewUniforms view_uniforms_;
  std::uint64_t view_serial_ = 0;  // draw() calls so far: a program whose `view` differs needs view_uniforms_
  GLuint downsample_ = 0, to_samples_ = 0, from_samples_ = 0, farthest_depth_ = 0;
  detail::ImpostorDrawer impostors_;
  GLint max_samples_ = 1;
  GLint max_size_ = 4096;
  GLint max_texture_size_ = 4096;
  float line_width_range_[2] = {1.f, 1.f};
};

}  // namespace

std::unique_ptr<Renderer> Renderer::create_headless() {
  return std::make_unique<GlRenderer>(detail::create_egl_context());
}

RenderOptions options_for(const CameraSet& set, RenderOptions base) {
  base.width = set.width;
  base.height = set.height;
  base.msaa = set.msaa;
  base.supersample = set.supersample;
  return base;
}

std::vector<RenderedView> render_camera_set(Renderer& renderer, const Scene& scene, const CameraSet& set,
                                            const RenderOptions& base) {
  const RenderOptions options = options_for(set, base);
  const Bounds bounds = scene.bounds();
  const float aspect = float(options.width) / float(options.height);
  std::vector<Camera> cameras;
  for (const CameraView& v : set.views) cameras.push_back(resolve(v, bounds, aspect));
  std::vector<image::Image> images = renderer.render_views(scene, cameras, options);
  std::vector<RenderedView> out;
  for (std::size_t i = 0; i < cameras.size(); ++i) out.push_back({cameras[i], std::move(images[i])});
  return out;
}

}  // namespace sylva::render
