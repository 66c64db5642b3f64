// Impostors inside the scene renderer (impostor_draw.h).
#include "libs/render/impostor_draw.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <set>
#include <string>
#include <string_view>

#include "libs/render/impostor_atlas.h"
#include "libs/render/shaders.h"

namespace sylva::render::detail {

namespace {

// A texture the drawer owns (kept between calls, not in the call's GlObjects).
GLuint upload_map(const std::vector<std::uint8_t>& rgba, int px, bool srgb, int mip_levels) {
  GLuint id = 0;
  glGenTextures(1, &id);
  glBindTexture(GL_TEXTURE_2D, id);
  upload_mipmapped_rgba8(rgba.data(), px, px, srgb, mip_levels);
  return id;
}

// A drawer-owned px x px 8-bit texture of one level, read with texelFetch only, its texels
// filled by the caller.
GLuint fetched_texture(GLenum internal_format, int px) {
  GLuint id = 0;
  glGenTextures(1, &id);
  glBindTexture(GL_TEXTURE_2D, id);
  glTexStorage2D(GL_TEXTURE_2D, 1, internal_format, px, px);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  return id;
}

// The march's depth and coverage, texel for texel (the shader's SYLVA_DEPTH_COVERAGE), gathered
// and uploaded a band of rows at a time: a whole-atlas copy (75 MB for a 6144-px atlas) would be
// new memory, and on this kind of machine touching new memory is what an upload costs most.
GLuint upload_depth_coverage(const ImpostorAtlas& a) {
  constexpr int kRows = 64;
  const int px = a.atlas_px;
  const GLuint id = fetched_texture(GL_RG8, px);
  std::vector<std::uint8_t> band(std::size_t(px) * kRows * 2);
  for (int y0 = 0; y0 < px; y0 += kRows) {
    const int rows = std::min(kRows, px - y0);
    tbb::parallel_for(0, rows, [&](int r) {
      const std::size_t row = std::size_t(y0 + r) * std::size_t(px);
      std::uint8_t* out = band.data() + std::size_t(r) * std::size_t(px) * 2;
      for (std::size_t x = 0; x < std::size_t(px); ++x) {
        out[2 * x] = a.normal_depth[4 * (row + x) + 3];
        out[2 * x + 1] = a.color[4 * (row + x) + 3];
      }
    });
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, y0, px, rows, GL_RG, GL_UNSIGNED_BYTE, band.data());
  }
  return id;
}

// The cull's cells: 4 x 4 texels where they tile a frame (one byte per 16 texels).
int empty_cell_px(const ImpostorGeometry& g) { return g.frame_px % 4 == 0 ? 4 : g.frame_px % 2 == 0 ? 2 : 1; }

// The cull's distances (the shader's SYLVA_EMPTY_DISTANCE), one R8 texel per cell. Its proof
// needs every read to stay in its frame, which a padding of 2^mip_levels texels guarantees (the
// impostor stage writes exactly that); with less, every distance is 0 and nothing is culled.
GLuint upload_empty_distance(const ImpostorAtlas& a) {
  const ImpostorGeometry& g = a.geometry;
  const int cell_px = empty_cell_px(g), side = a.atlas_px / cell_px;
  std::vector<std::uint8_t> d(std::size_t(side) * std::size_t(side), 0);
  if (g.mip_levels < 30 && g.padding_px >= (1 << g.mip_levels)) d = impostor_empty_distance(a, cell_px);
  const GLuint id = fetched_texture(GL_R8, side);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, side, side, GL_RED, GL_UNSIGNED_BYTE, d.data());
  return id;
}

void delete_kept_textures(GLuint color, GLuint normal_depth, GLuint empty_distance, GLuint depth_coverage) {
  const GLuint t[4] = {color, normal_depth, empty_distance, depth_coverage};
  glDeleteTextures(4, t);
}

}  // namespace

void set_impostor_uniforms(GLuint program, const ImpostorGeometry& g, int parallax_steps) {
  auto u = [&](const char* n) { return glGetUniformLocation(program, n); };
  glUniform1i(u("u_frames"), g.frames_per_side);
  glUniform1i(u("u_hemi"), g.hemi);
  glUniform3fv(u("u_center"), 1, g.center.data());
  glUniform1f(u("u_radius"), g.radius);
  glUniform1f(u("u_half_extent"), g.half_extent);
  glUniform1f(u("u_padding"), float(g.padding_px) / float(g.frame_px));
  glUniform1i(u("u_parallax_steps"), std::clamp(parallax_steps, 0, 64));
  glUniform1i(u("u_mip_levels"), g.mip_levels);
  glUniform1i(u("u_empty_cell_px"), empty_cell_px(g));
  glUniform1f(u("u_atlas_px"), float(g.frames_per_side * g.frame_px));
}

GLuint ImpostorDrawer::program(int steps, bool scene_depth) {
  steps = std::clamp(steps, 0, 64);
  if (const auto it = programs_.find({steps, scene_depth}); it != programs_.end()) return it->second;
  static constexpr std::string_view kUniform = "uniform int u_parallax_steps;";
  std::string fragment = kOctahedralImpostorFrag;
  const std::size_t at = fragment.find(kUniform);
  if (at == std::string::npos)
    throw RenderError("the impostor fragment shader declares no 'uniform int u_parallax_steps;'");
  fragment.replace(at, kUniform.size(), "const int u_parallax_steps = " + std::to_string(steps) + ";");
  // Both of the shader's exact options: one fetch per march step, the cull of fragments that
  // would read nothing stored.
  fragment = with_prelude(fragment,
                          std::string("#define SYLVA_DEPTH_COVERAGE\n#define SYLVA_EMPTY_DISTANCE\n") +
                              (scene_depth ? "#define SYLVA_SCENE_DEPTH\n" : ""),
                          "impostor fragment");
  const GLuint id = link_program(kOctahedralImpostorVert, fragment.c_str(), "octahedral impostor");
  programs_.emplace(std::pair{steps, scene_depth}, id);
  return id;
}

void ImpostorDrawer::destroy() {
  for (const auto& [steps, id] : programs_) glDeleteProgram(id);
  programs_.clear();
  for (const Kept& k : kept_)
    delete_kept_textures(k.color, k.normal_depth, k.empty_distance, k.depth_coverage);
  kept_.clear();
}

ImpostorDrawer::Uploaded ImpostorDrawer::upload(GlObjects& gl, const std::vector<ImpostorSet>& sets,
                                                GLint max_texture_px, bool scene_depth) {
  Uploaded up;
  // Maps of atlases that no longer exist are deleted first (whatever this call draws).
  std::erase_if(kept_, [](const Kept& k) {
    if (!k.atlas.expired()) return false;
    delete_kept_textures(k.color, k.normal_depth, k.empty_distance, k.depth_coverage);
    return true;
  });
  if (sets.empty()) return up;
  for (const ImpostorSet& s : sets) program(s.parallax_steps, scene_depth);
  for (const ImpostorSet& s : sets) {
    if (!s.atlas) throw RenderError("an impostor set has no atlas");
    const ImpostorAtlas& a = *s.atlas;
    const ImpostorGeometry& g = a.geometry;
    const std::size_t bytes = std::size_t(a.atlas_px) * std::size_t(a.atlas_px) * 4;
    if (g.frames_per_side < 2 || g.frame_px < 1 || a.atlas_px != g.frames_per_side * g.frame_px ||
        a.atlas_px > max_texture_px || a.color.size() != bytes || a.normal_depth.size() != bytes)
      throw RenderError("impostor '" + a.name + "': its atlas is not " + std::to_string(g.frames_per_side) +
                        " x " + std::to_string(g.frame_px) + " px frames with both maps (at most " +
                        std::to_string(max_texture_px) + " px here)");
    if (!(g.radius > 0) || !(g.half_extent >= g.radius) || g.padding_px < 0 || 2 * g.padding_px >= g.frame_px)
      throw RenderError(
          "impostor '" + a.name +
          "': geometry is inconsistent (radius > 0, half extent >= radius, padding < frame / 2)");
    auto k =
        std::find_if(kept_.begin(), kept_.end(), [&](const Kept& e) { return e.atlas.lock() == s.atlas; });
    if (k == kept_.end()) {
      const Kept fresh{s.atlas, upload_map(a.color, a.atlas_px, true, g.mip_levels),
                       upload_map(a.normal_depth, a.atlas_px, false, g.mip_levels), upload_empty_distance(a),
                       upload_depth_coverage(a)};
      // A map that did not upload (out of memory) is not kept: the next call tries again.
      if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
        delete_kept_textures(fresh.color, fresh.normal_depth, fresh.empty_distance, fresh.depth_coverage);
        throw RenderError("impostor '" + a.name + "': its maps could not be uploaded (GL error " +
                          std::to_string(e) + ")");
      }
      kept_.push_back(fresh);
      k = kept_.end() - 1;
    }
    up.color.push_back(k->color);
    up.normal_depth.push_back(k->normal_depth);
    up.empty_distance.push_back(k->empty_distance);
    up.depth_coverage.push_back(k->depth_coverage);
  }
  const std::vector<float> corners = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
  up.vao = gl.vertex_array();
  glBindVertexArray(up.vao);
  glBindBuffer(GL_ARRAY_BUFFER, upload_array(gl, GL_ARRAY_BUFFER, corners));
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  up.instances = gl.buffer();
  glBindBuffer(GL_ARRAY_BUFFER, up.instances);
  for (GLuint c = 0; c < 4; ++c) {
    glEnableVertexAttribArray(1 + c);
    glVertexAttribDivisor(1 + c, 1);
  }
  glBindVertexArray(0);
  return up;
}

namespace {

// One instance of one set, by its centre's view-space z (more negative = farther).
struct DrawKey {
  float z;
  std::uint32_t set, instance;
};

// Every instance of every set, far to near (stable: equal depths keep set and instance order).
std::vector<DrawKey> far_to_near(const std::vector<ImpostorSet>& sets, const Mat4& view) {
  std::vector<DrawKey> keys;
  for (std::size_t s = 0; s < sets.size(); ++s)
    for (std::size_t i = 0; i < sets[s].instances.size(); ++i) {
      const Vec3 w = (sets[s].instances[i] * sets[s].atlas->geometry.center.homogeneous()).hnormalized();
      keys.push_back({(view * w.homogeneous())(2), std::uint32_t(s), std::uint32_t(i)});
    }
  std::stable_sort(keys.begin(), keys.end(), [](const DrawKey& a, const DrawKey& b) { return a.z < b.z; });
  return keys;
}

// The instances' model matrices in draw order into the instance buffer (vao bound).
void upload_models(const std::vector<DrawKey>& keys, const std::vector<ImpostorSet>& sets,
                   const ImpostorDrawer::Uploaded& up) {
  std::vector<float> models;
  models.reserve(keys.size() * 16);
  for (const DrawKey& k : keys) {
    const Mat4& m = sets[k.set].instances[k.instance];
    models.insert(models.end(), m.data(), m.data() + 16);
  }
  glBindVertexArray(up.vao);
  glBindBuffer(GL_ARRAY_BUFFER, up.instances);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(models.size() * sizeof(float)), models.data(), GL_STREAM_DRAW);
}

// The view's uniforms and the texture units of program `id` (in use).
void set_view_uniforms(GLuint id, const Mat4& view, const Mat4& proj, const Camera& cam,
                       const Lighting& lighting, bool scene_depth) {
  const Vec3 l =
      lighting.direction_to_light.norm() > 0 ? lighting.direction_to_light.normalized() : Vec3::UnitY();
  auto u = [&](const char* n) { return glGetUniformLocation(id, n); };
  glUniformMatrix4fv(u("u_view"), 1, GL_FALSE, view.data());
  glUniformMatrix4fv(u("u_proj"), 1, GL_FALSE, proj.data());
  glUniform3fv(u("u_eye"), 1, cam.eye.data());
  glUniform3fv(u("u_ambient"), 1, lighting.ambient.data());
  glUniform3fv(u("u_light_color"), 1, lighting.light_color.data());
  glUniform3fv(u("u_light_dir"), 1, l.data());
  glUniform1i(u("u_color"), 0);
  glUniform1i(u("u_normal_depth"), 1);
  glUniform1i(u("u_empty_distance"), 2);
  glUniform1i(u("u_depth_coverage"), 3);
  if (scene_depth) glUniform1i(u("u_scene_depth"), 4);
}

// Set s's four maps on texture units 0..3.
void bind_set_maps(const ImpostorDrawer::Uploaded& up, std::size_t s) {
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, up.color[s]);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, up.normal_depth[s]);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, up.empty_distance[s]);
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, up.depth_coverage[s]);
}

}  // namespace

void ImpostorDrawer::draw(const std::vector<ImpostorSet>& sets, const Uploaded& up, const Camera& cam,
                          float aspect, const Lighting& lighting, GLuint scene_depth) {
  if (sets.empty()) return;
  // Far to near over all sets.
  const Mat4 view = cam.view_matrix();
  const std::vector<DrawKey> keys = far_to_near(sets, view);
  if (keys.empty()) return;
  upload_models(keys, sets, up);

  // The view's uniforms, set on each program once (before its first run).
  const Mat4 proj = cam.projection_matrix(aspect);
  std::set<GLuint> viewed;  // programs holding this view's uniforms
  auto use = [&](int steps) {
    const GLuint id = program(steps, scene_depth != 0);
    glUseProgram(id);
    if (viewed.insert(id).second) set_view_uniforms(id, view, proj, cam, lighting, scene_depth != 0);
    return id;
  };
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_FALSE);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  if (scene_depth) {
    glActiveTexture(GL_TEXTURE4);
    glBindTexture(GL_TEXTURE_2D, scene_depth);
  }
  // One instanced draw per run of instances of the same set.
  std::size_t current = sets.size();
  for (std::size_t begin = 0; begin < keys.size();) {
    std::size_t end = begin + 1;
    while (end < keys.size() && keys[end].set == keys[begin].set) ++end;
    const std::size_t s = keys[begin].set;
    if (s != current) {
      current = s;
      set_impostor_uniforms(use(sets[s].parallax_steps), sets[s].atlas->geometry, sets[s].parallax_steps);
      bind_set_maps(up, s);
    }
    // The run's matrices start at instance `begin` of the sorted buffer.
    for (GLuint c = 0; c < 4; ++c)
      glVertexAttribPointer(
          1 + c, 4, GL_FLOAT, GL_FALSE, 16 * sizeof(float),
          reinterpret_cast<const void*>(std::uintptr_t((begin * 16 + c * 4) * sizeof(float))));
    glDrawArraysInstanced(GL_TRIANGLES, 0, 6, GLsizei(end - begin));
    begin = end;
  }
  if (scene_depth) {
    glActiveTexture(GL_TEXTURE4);
    glBindTexture(GL_TEXTURE_2D, 0);
  }
  glActiveTexture(GL_TEXTURE0);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glBindVertexArray(0);
}

}  // namespace sylva::render::detail
