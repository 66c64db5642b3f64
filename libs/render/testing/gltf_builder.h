// Test and benchmark helper: builds small glTF models in memory with tinygltf and writes them as
// .glb, so tests exercise the real loading path (tinygltf, Draco, instancing) end to end.
// Not part of the renderer's API; linked only by tests and benchmarks (sylva_render_testing).
#pragma once

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <vector>

#include "libs/image/image.h"
#include "libs/render/scene.h"

namespace sylva::render::testing {

struct PrimitiveData {
  int mode = TINYGLTF_MODE_TRIANGLES;
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<Vec2> texcoords;
  std::vector<Vec4> colors;
  std::vector<float> sizes;            // written as _SIZE
  std::vector<std::uint32_t> indices;  // empty: non-indexed
  int material = -1;
  bool draco = false;  // triangles only: POSITION, NORMAL, TEXCOORD_0 and indices Draco-compressed
};

struct MaterialData {
  Vec4 base_color = Vec4::Ones();
  int texture = -1;  // from add_texture
  std::string alpha_mode = "OPAQUE";
  float alpha_cutoff = 0.5f;
  bool double_sided = false;
  bool unlit = false;
};

struct NodeData {
  int mesh = -1;
  Vec3 translation = Vec3::Zero();
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();
  Vec3 scale = Vec3::Ones();
  std::vector<int> children;
  // EXT_mesh_gpu_instancing; all empty = not instanced. Non-empty arrays must agree in length.
  std::vector<Vec3> instance_translations;
  std::vector<Eigen::Quaternionf> instance_rotations;
  std::vector<Vec3> instance_scales;
};

class GltfBuilder {
 public:
  GltfBuilder();
  int add_texture(const image::Image& img, bool nearest = true);  // embedded PNG
  int add_material(const MaterialData& m);
  int add_mesh(const std::vector<PrimitiveData>& primitives, const std::string& name = {});
  int add_node(const NodeData& n);
  void add_root(int node);  // to scene 0
  tinygltf::Model& model() { return model_; }
  void write_glb(const std::filesystem::path& path) const;  // throws std::runtime_error

 private:
  int add_view(const void* data, std::size_t bytes, int target);
  int add_accessor(const void* data, std::size_t count, int type, int component_type, int target,
                   bool min_max = false);
  tinygltf::Model model_;
};

// Canned geometry.
// A size x size quad in the z = 0 plane centred at the origin, normal +Z, uvs (0,0) top-left.
PrimitiveData quad(float size, int material = -1);
// An axis-aligned cube of edge `size` centred at the origin, 24 vertices with face normals and
// per-face uvs covering the whole texture.
PrimitiveData cube(float size, int material = -1);
// A dense wavy sheet of n x n quads (2 n^2 triangles) spanning [-0.5, 0.5]^2 in x/y.
PrimitiveData dense_grid(int n, int material = -1);

}  // namespace sylva::render::testing
