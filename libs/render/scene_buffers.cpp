// A scene's GL buffers (scene_buffers.h). Meshes naming shared geometry (a forest's species
// levels, drawn by every view of a walk) keep their vertex and element buffers between calls:
// uploading them again per view cost more than drawing some views.
#include "libs/render/scene_buffers.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

#include "libs/render/renderer.h"
#include "libs/render/scene_programs.h"

namespace sylva::render::detail {
namespace {

// The instance's model matrix and normal matrix (inverse transpose; kInstanceFloats).
void fill_instance(const Mat4& m, float* out) {
  std::memcpy(out, m.data(), 16 * sizeof(float));
  Eigen::Matrix3f n = m.topLeftCorner<3, 3>();
  const float det = n.determinant();
  if (std::abs(det) > 1e-20f) n = n.inverse().transpose().eval();
  std::memcpy(out + 16, n.data(), 9 * sizeof(float));
}

// The per-instance matrices of the bound vertex array, from `instance_buffer`.
void attach_instance_matrices(GLuint instance_buffer) {
  glBindBuffer(GL_ARRAY_BUFFER, instance_buffer);
  const GLsizei stride = kInstanceFloats * sizeof(float);
  for (GLuint c = 0; c < 4; ++c) {
    glEnableVertexAttribArray(SceneAttribute::kModel + c);
    glVertexAttribPointer(SceneAttribute::kModel + c, 4, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(std::uintptr_t(c * 4 * sizeof(float))));
    glVertexAttribDivisor(SceneAttribute::kModel + c, 1);
  }
  for (GLuint c = 0; c < 3; ++c) {
    glEnableVertexAttribArray(SceneAttribute::kNormalMatrix + c);
    glVertexAttribPointer(SceneAttribute::kNormalMatrix + c, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(std::uintptr_t((16 + c * 3) * sizeof(float))));
    glVertexAttribDivisor(SceneAttribute::kNormalMatrix + c, 1);
  }
}

}  // namespace

bool blended(const Scene& scene, const Primitive& p) {
  return p.material >= 0 && scene.materials[std::size_t(p.material)].alpha_mode == AlphaMode::kBlend;
}

void check_primitive(const Scene& scene, const Primitive& p, bool with_sizes_and_copies) {
  const std::size_t n = p.positions.size();
  auto bad = [&](const std::string& what) {
    throw RenderError("invalid primitive in scene '" + scene.source + "': " + what);
  };
  if ((!p.normals.empty() && p.normals.size() != n) || (!p.texcoords.empty() && p.texcoords.size() != n) ||
      (!p.colors.empty() && p.colors.size() != n) ||
      (with_sizes_and_copies &&
       ((!p.sizes.empty() && p.sizes.size() != n) || (!p.copies.empty() && p.copies.size() != n))))
    bad("attribute arrays differ in length from positions");
  for (std::uint32_t i : p.indices)
    if (i >= n) bad("index " + std::to_string(i) + " out of range");
  if (p.material >= 0 && std::size_t(p.material) >= scene.materials.size()) bad("material out of range");
  if (p.material >= 0) {
    const int t = scene.materials[std::size_t(p.material)].base_color_texture;
    if (t >= 0 && std::size_t(t) >= scene.textures.size()) bad("texture out of range");
  }
}

void SceneBuffers::destroy() {
  for (const KeptGeometry& k : kept_) glDeleteBuffers(GLsizei(k.buffers.size()), k.buffers.data());
  kept_.clear();
}

void SceneBuffers::drop_dead() {
  std::erase_if(kept_, [](const KeptGeometry& k) {
    if (!k.owner.expired()) return false;
    glDeleteBuffers(GLsizei(k.buffers.size()), k.buffers.data());
    return true;
  });
}

void SceneBuffers::keep(const Scene& scene) {
  for (const Mesh& mesh : scene.meshes) {
    if (!mesh.shared_geometry) continue;
    for (const Primitive& p : mesh.primitives) check_primitive(scene, p);
    kept_buffers(scene, mesh);
  }
}

// Binds the vertex arrays of a primitive (the buffers already exist) into the bound VAO.
void SceneBuffers::attach_vertex_buffers(const VertexBuffers& vb) {
  auto attach = [](GLuint location, GLuint buffer, GLint comps) {
    if (!buffer) return;
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glEnableVertexAttribArray(location);
    glVertexAttribPointer(location, comps, GL_FLOAT, GL_FALSE, 0, nullptr);
  };
  attach(SceneAttribute::kPosition, vb.position, 3);
  attach(SceneAttribute::kNormal, vb.normal, 3);
  attach(SceneAttribute::kTexcoord, vb.texcoord, 2);
  attach(SceneAttribute::kColor, vb.color, 4);
  attach(SceneAttribute::kSize, vb.size, 1);
  attach(SceneAttribute::kCopies, vb.copies, 1);
}

// A primitive's vertex arrays and, unless it is blended, its element buffer, in buffers named
// by `new_buffer()`.
template <typename NewBuffer>
SceneBuffers::PrimitiveBuffers SceneBuffers::upload_buffers(const Primitive& p, bool blend,
                                                            NewBuffer&& new_buffer) {
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
const std::vector<SceneBuffers::PrimitiveBuffers>& SceneBuffers::kept_buffers(const Scene& scene,
                                                                              const Mesh& mesh) {
  auto same = [&](const KeptGeometry& k) {
    if (k.key != mesh.shared_geometry.get()) return false;
    const std::shared_ptr<const void> alive = k.owner.lock();
    return alive && !alive.owner_before(mesh.shared_geometry) && !mesh.shared_geometry.owner_before(alive);
  };
  auto it = std::find_if(kept_.begin(), kept_.end(), same);
  if (it != kept_.end()) {
    bool fits = it->primitives.size() == mesh.primitives.size();
    for (std::size_t i = 0; fits && i < mesh.primitives.size(); ++i)
      fits = it->primitives[i].vertices == mesh.primitives[i].positions.size() &&
             it->primitives[i].indices == mesh.primitives[i].indices.size();
    if (fits) return it->primitives;
    glDeleteBuffers(GLsizei(it->buffers.size()), it->buffers.data());
    kept_.erase(it);
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
    throw RenderError("mesh '" + mesh.name + "' could not be uploaded (GL error " + std::to_string(e) + ")");
  }
  kept_.push_back(std::move(k));
  return kept_.back().primitives;
}

GpuMesh SceneBuffers::upload_mesh(GlObjects& gl, const Scene& scene, const Mesh& mesh, UploadedScene& up) {
  GpuMesh gm;
  gm.source = &mesh;
  if (mesh.instances.empty()) return gm;
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
      attach_instance_matrices(instance_buffer);
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
  return gm;
}

UploadedScene SceneBuffers::upload(GlObjects& gl, const Scene& scene) {
  drop_dead();
  UploadedScene up;
  for (const Texture& t : scene.textures) up.textures.push_back(upload_texture(gl, t));
  for (const Mesh& mesh : scene.meshes) up.meshes.push_back(upload_mesh(gl, scene, mesh, up));
  return up;
}

}  // namespace sylva::render::detail
