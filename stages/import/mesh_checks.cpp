// The last checks of an imported mesh (mesh_checks.h). Degenerate faces are dropped here rather
// than by the readers (Assimp's FindDegenerates turns them into lines and points, tinygltf keeps
// them) so both readers count and report them the same way.
#include "stages/import/mesh_checks.h"

#include <algorithm>
#include <cmath>

namespace sylva::import {

namespace {

std::string quoted_list(const std::vector<std::string>& names, std::size_t max = 5) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < max; ++i) out += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > max) out += " and " + std::to_string(names.size() - max) + " more";
  return out;
}

std::string label(const tree::SourcePrimitive& p, std::size_t i) {
  return "primitive " + std::to_string(i) + " ('" + p.name + "')";
}

bool finite(const tree::Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool degenerate(const tree::SourcePrimitive& p, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (a == b || b == c || a == c) return true;
  const tree::Vec3f &p0 = p.positions[a], &p1 = p.positions[b], &p2 = p.positions[c];
  const double ux = double(p1.x) - p0.x, uy = double(p1.y) - p0.y, uz = double(p1.z) - p0.z;
  const double vx = double(p2.x) - p0.x, vy = double(p2.y) - p0.y, vz = double(p2.z) - p0.z;
  return uy * vz - uz * vy == 0 && uz * vx - ux * vz == 0 && ux * vy - uy * vx == 0;
}

void fix_normals(tree::SourcePrimitive& p, std::size_t i, std::string_view source,
                 std::vector<std::string>& warnings) {
  for (tree::Vec3f& n : p.normals) {
    const double len = std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z);
    if (!std::isfinite(len) || len < 1e-12) {
      warnings.push_back(std::string(source) + ": warning: " + label(p, i) +
                         ": a normal is zero or not finite: the primitive's normals are dropped");
      p.normals.clear();
      return;
    }
    n = tree::Vec3f{float(n.x / len), float(n.y / len), float(n.z / len)};
  }
}

void clamp_material(tree::SourceMaterial& m, std::string_view source, std::vector<std::string>& warnings) {
  bool clamped = false;
  auto clamp01 = [&](float& v) {
    const float c = std::isfinite(v) ? std::clamp(v, 0.f, 1.f) : 1.f;
    if (c != v) clamped = true;
    v = c;
  };
  for (float& c : m.base_color) clamp01(c);
  clamp01(m.metallic);
  clamp01(m.roughness);
  clamp01(m.alpha_cutoff);
  if (clamped)
    warnings.push_back(std::string(source) + ": warning: material '" + m.name +
                       "': colour, metallic, roughness or alpha cutoff outside [0, 1], clamped");
}

// Materials no primitive uses (Assimp's OBJ reader adds a "DefaultMaterial") and images no
// kept material uses go; the indices that remain are renumbered in order.
void drop_unused(tree::SourceGeometry& g) {
  std::vector<std::int64_t> material_slot(g.materials.size(), -1), image_slot(g.images.size(), -1);
  for (const tree::SourcePrimitive& p : g.primitives) material_slot[p.material] = 0;
  std::vector<tree::SourceMaterial> materials;
  for (std::size_t i = 0; i < g.materials.size(); ++i) {
    if (material_slot[i] < 0) continue;
    material_slot[i] = std::int64_t(materials.size());
    materials.push_back(std::move(g.materials[i]));
  }
  std::vector<tree::SourceImage> images;
  for (tree::SourceMaterial& m : materials) {
    if (m.base_color_image < 0) continue;
    std::int64_t& slot = image_slot[std::size_t(m.base_color_image)];
    if (slot < 0) {
      slot = std::int64_t(images.size());
      images.push_back(std::move(g.images[std::size_t(m.base_color_image)]));
    }
    m.base_color_image = std::int32_t(slot);
  }
  for (tree::SourcePrimitive& p : g.primitives) p.material = std::uint32_t(material_slot[p.material]);
  g.materials = std::move(materials);
  g.images = std::move(images);
}

}  // namespace

void check_mesh_limits(std::string_view source, std::size_t vertices, std::size_t triangles,
                       const MeshOptions& options) {
  if (vertices > options.max_vertices)
    throw MeshError(source, "the model has more than " + std::to_string(options.max_vertices) +
                                " vertices (the import's limit, tree::kMaxSourceVertices)");
  if (triangles > options.max_triangles)
    throw MeshError(source, "the model has more than " + std::to_string(options.max_triangles) +
                                " triangles (the import's limit, tree::kMaxSourceTriangles)");
}

void finish_geometry(MeshImport& m, std::string_view source) {
  tree::SourceGeometry& g = m.geometry;
  std::size_t dropped = 0;
  std::vector<std::string> dropped_in, emptied;
  for (std::size_t i = 0; i < g.primitives.size(); ++i) {
    tree::SourcePrimitive& p = g.primitives[i];
    for (std::size_t v = 0; v < p.positions.size(); ++v)
      if (!finite(p.positions[v]))
        throw MeshError(source, label(p, i) + ": vertex " + std::to_string(v) + " is not finite");
    fix_normals(p, i, source, m.warnings);
    if (std::any_of(p.uvs.begin(), p.uvs.end(), [](const std::array<float, 2>& t) {
          return !std::isfinite(t[0]) || !std::isfinite(t[1]);
        })) {
      m.warnings.push_back(std::string(source) + ": warning: " + label(p, i) +
                           ": a texture coordinate is not finite: the primitive's uvs are dropped");
      p.uvs.clear();
    }
    std::size_t kept = 0;
    for (std::size_t t = 0; t + 2 < p.indices.size(); t += 3) {
      const std::uint32_t a = p.indices[t], b = p.indices[t + 1], c = p.indices[t + 2];
      if (degenerate(p, a, b, c)) continue;
      p.indices[kept++] = a;
      p.indices[kept++] = b;
      p.indices[kept++] = c;
    }
    if (kept < p.indices.size()) {
      dropped += (p.indices.size() - kept) / 3;
      dropped_in.push_back(p.name);
      p.indices.resize(kept);
    }
  }
  if (dropped > 0)
    m.warnings.push_back(std::string(source) + ": warning: " + std::to_string(dropped) +
                         " degenerate triangle(s) (a repeated vertex or zero area) dropped, in " +
                         quoted_list(dropped_in));
  std::vector<tree::SourcePrimitive> kept;
  for (tree::SourcePrimitive& p : g.primitives) {
    if (p.indices.empty()) {
      emptied.push_back(p.name);
    } else {
      kept.push_back(std::move(p));
    }
  }
  g.primitives = std::move(kept);
  if (!emptied.empty())
    m.warnings.push_back(std::string(source) + ": warning: " + std::to_string(emptied.size()) +
                         " primitive(s) without triangles dropped: " + quoted_list(emptied));
  drop_unused(g);
  for (tree::SourceMaterial& mat : g.materials) clamp_material(mat, source, m.warnings);
  m.facts.vertices = m.facts.triangles = 0;
  for (const tree::SourcePrimitive& p : g.primitives) {
    m.facts.vertices += p.positions.size();
    m.facts.triangles += p.indices.size() / 3;
  }
}

}  // namespace sylva::import
