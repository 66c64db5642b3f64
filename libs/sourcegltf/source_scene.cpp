// Why the conversion computes normals: glTF viewers shade a primitive without NORMAL flat (and
// sylva's renderer needs them), while OBJ, PLY and 3DS files often carry none; the hierarchy
// works without them, so the reader keeps the file's truth and this library fills the gap at
// the moment the geometry is drawn.
#include "libs/sourcegltf/source_scene.h"

#include <cmath>
#include <stdexcept>

namespace sylva::sourcegltf {

namespace {

gltf::AlphaMode alpha_mode(tree::AlphaMode m) {
  switch (m) {
    case tree::AlphaMode::kMask:
      return gltf::AlphaMode::kMask;
    case tree::AlphaMode::kBlend:
      return gltf::AlphaMode::kBlend;
    case tree::AlphaMode::kOpaque:
      break;
  }
  return gltf::AlphaMode::kOpaque;
}

void push_unit(std::vector<float>& out, double x, double y, double z) {
  const double len = std::sqrt(x * x + y * y + z * z);
  if (!(len > 1e-30) || !std::isfinite(len)) {
    out.insert(out.end(), {0.f, 1.f, 0.f});
    return;
  }
  out.insert(out.end(), {float(x / len), float(y / len), float(z / len)});
}

// Area-weighted vertex normals: the sum of the adjacent faces' cross products (twice their
// area times their unit normal).
std::vector<float> computed_normals(const tree::SourcePrimitive& p) {
  std::vector<double> acc(p.positions.size() * 3, 0.0);
  for (std::size_t t = 0; t + 2 < p.indices.size(); t += 3) {
    const tree::Vec3f& a = p.positions[p.indices[t]];
    const tree::Vec3f& b = p.positions[p.indices[t + 1]];
    const tree::Vec3f& c = p.positions[p.indices[t + 2]];
    const double ux = double(b.x) - a.x, uy = double(b.y) - a.y, uz = double(b.z) - a.z;
    const double vx = double(c.x) - a.x, vy = double(c.y) - a.y, vz = double(c.z) - a.z;
    const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    for (int k = 0; k < 3; ++k) {
      const std::size_t v = p.indices[t + std::size_t(k)];
      acc[3 * v] += nx;
      acc[3 * v + 1] += ny;
      acc[3 * v + 2] += nz;
    }
  }
  std::vector<float> out;
  out.reserve(acc.size());
  for (std::size_t v = 0; v < p.positions.size(); ++v)
    push_unit(out, acc[3 * v], acc[3 * v + 1], acc[3 * v + 2]);
  return out;
}

gltf::Primitive primitive(const tree::SourcePrimitive& p, int material_offset) {
  gltf::Primitive out;
  out.mode = gltf::PrimitiveMode::kTriangles;
  out.positions.reserve(p.positions.size() * 3);
  for (const tree::Vec3f& v : p.positions) out.positions.insert(out.positions.end(), {v.x, v.y, v.z});
  if (p.normals.empty()) {
    out.normals = computed_normals(p);
  } else {
    out.normals.reserve(p.normals.size() * 3);
    for (const tree::Vec3f& n : p.normals) push_unit(out.normals, n.x, n.y, n.z);
  }
  out.texcoords.reserve(p.uvs.size() * 2);
  for (const auto& uv : p.uvs) out.texcoords.insert(out.texcoords.end(), {uv[0], uv[1]});
  out.indices = p.indices;
  out.material = material_offset + static_cast<int>(p.material);
  return out;
}

gltf::Material material(const tree::SourceMaterial& m, int image_offset) {
  gltf::Material out;
  out.name = m.name;
  out.base_color = m.base_color;
  if (m.base_color_image >= 0) out.base_color_texture.image = image_offset + m.base_color_image;
  out.alpha_mode = alpha_mode(m.alpha_mode);
  out.alpha_cutoff = m.alpha_cutoff;
  out.double_sided = m.double_sided;
  out.metallic = m.metallic;
  out.roughness = m.roughness;
  return out;
}

}  // namespace

int append_source_mesh(gltf::Scene& scene, const tree::SourceGeometry& g, const std::string& mesh_name) {
  if (g.empty()) throw std::invalid_argument("append_source_mesh: the tree has no source geometry");
  const int image_offset = static_cast<int>(scene.images.size());
  const int material_offset = static_cast<int>(scene.materials.size());
  for (const tree::SourceImage& im : g.images) scene.images.push_back({im.name, im.mime_type, im.bytes, {}});
  for (const tree::SourceMaterial& m : g.materials) scene.materials.push_back(material(m, image_offset));
  gltf::Mesh mesh;
  mesh.name = mesh_name;
  mesh.primitives.reserve(g.primitives.size());
  for (const tree::SourcePrimitive& p : g.primitives)
    mesh.primitives.push_back(primitive(p, material_offset));
  scene.meshes.push_back(std::move(mesh));
  return static_cast<int>(scene.meshes.size()) - 1;
}

gltf::Scene source_scene(const tree::SourceGeometry& g, const std::string& node_name) {
  gltf::Scene scene;
  gltf::Node node;
  node.name = node_name;
  node.mesh = append_source_mesh(scene, g, node_name);
  scene.nodes.push_back(std::move(node));
  scene.roots = {0};
  return scene;
}

std::size_t source_triangle_count(const tree::SourceGeometry& g) {
  std::size_t n = 0;
  for (const tree::SourcePrimitive& p : g.primitives) n += p.indices.size() / 3;
  return n;
}

}  // namespace sylva::sourcegltf
