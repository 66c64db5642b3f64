// Private: a scene's GL buffers for the scene renderer (gl_renderer.cpp). Per call: the scene's
// textures, its meshes' instance matrices and the vertex arrays of every mesh that names no
// shared geometry. Kept between calls: the buffers of meshes naming shared geometry
// (Mesh::shared_geometry), while the name lives. Every function expects the context current.
//
// Opaque and masked primitives get a vertex array with their element buffer and the instance
// matrices as per-instance attributes (one instanced draw); blended ones a vertex array without
// either (the blend pass draws each instance with the matrices as constant attributes and its
// sorted elements from UploadedScene::blend_indices).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "libs/render/gl_util.h"
#include "libs/render/scene.h"

namespace sylva::render::detail {

struct GpuPrimitive {
  const Primitive* source = nullptr;
  GLuint vao_instanced = 0;  // vertex arrays + per-instance matrices
  GLuint vao_single = 0;  // vertex arrays (elements from UploadedScene::blend_indices); matrices as constants
  GLsizei index_count = 0;
  bool blend = false;
};

struct GpuMesh {
  const Mesh* source = nullptr;
  std::vector<GpuPrimitive> primitives;  // empty when the mesh has no instance
  std::vector<float> instance_data;      // kInstanceFloats (scene_programs.h) per instance
  bool mirrored = false;                 // some instance matrix has a negative determinant
};

// What one call drew with (names owned by the call's GlObjects, or kept by SceneBuffers).
struct UploadedScene {
  std::vector<GLuint> textures;  // Scene::textures
  std::vector<GpuMesh> meshes;   // Scene::meshes
  GLuint blend_indices = 0;      // every blended draw's sorted elements of one view (0: no BLEND primitive)
};

// Whether `p` is drawn in the blend pass (its material's alpha mode is BLEND).
bool blended(const Scene& scene, const Primitive& p);

// The GL side trusts these; load_gltf_scene guarantees them, hand-built scenes are checked.
// Throws RenderError("invalid primitive in scene '<source>': ..."). `with_sizes_and_copies`
// false skips Primitive::sizes and ::copies, which the impostor bake does not read.
void check_primitive(const Scene& scene, const Primitive& p, bool with_sizes_and_copies = true);

class SceneBuffers {
 public:
  SceneBuffers() = default;
  SceneBuffers(const SceneBuffers&) = delete;
  SceneBuffers& operator=(const SceneBuffers&) = delete;
  // Deletes the kept buffers (the renderer's destructor).
  void destroy();

  // Meshes whose buffers are kept (Renderer::kept_geometry).
  std::size_t kept() const { return kept_.size(); }
  // Deletes the kept buffers whose name no longer lives (first thing at every call).
  void drop_dead();
  // Checks and keeps the buffers of every mesh of `scene` naming shared geometry, without
  // looking at instances or textures (Renderer::prepare). Throws RenderError.
  void keep(const Scene& scene);
  // Uploads `scene` for one call (names in `gl`, or kept), drop_dead() first. Throws RenderError.
  UploadedScene upload(GlObjects& gl, const Scene& scene);

 private:
  struct VertexBuffers {
    GLuint position = 0, normal = 0, texcoord = 0, color = 0, size = 0, copies = 0;
  };
  // A primitive's vertex arrays and, unless it is blended, its element buffer.
  struct PrimitiveBuffers {
    VertexBuffers vb;
    GLuint elements = 0;
    std::size_t vertices = 0, indices = 0;  // the counts uploaded
  };
  // The buffers of a Mesh::shared_geometry, kept while the geometry's name lives.
  struct KeptGeometry {
    std::weak_ptr<const void> owner;
    const void* key = nullptr;
    std::vector<PrimitiveBuffers> primitives;
    std::vector<GLuint> buffers;  // every name in `primitives`
  };

  template <typename NewBuffer>
  static PrimitiveBuffers upload_buffers(const Primitive& p, bool blend, NewBuffer&& new_buffer);
  static void attach_vertex_buffers(const VertexBuffers& vb);
  const std::vector<PrimitiveBuffers>& kept_buffers(const Scene& scene, const Mesh& mesh);
  GpuMesh upload_mesh(GlObjects& gl, const Scene& scene, const Mesh& mesh, UploadedScene& up);

  std::vector<KeptGeometry> kept_;
};

}  // namespace sylva::render::detail
