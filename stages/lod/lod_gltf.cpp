// glTF output of a LOD chain: per-level primitives, MSFT_lod linking, extras.
// Seeds: Zhang et al. 2017 §6 (meshes and semi-transparent lines per level); MSFT_lod.
#include "stages/lod/lod_gltf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>

#include "libs/gltf/writer.h"

namespace sylva::lod {

namespace {

std::array<float, 4> rgba(const tree::Color& c, double a) {
  return {c.r, c.g, c.b, static_cast<float>(std::clamp(a, 0.0, 1.0))};
}

// Materials: 0 bark, 1 branch lines, 2 leaves, 3 needle lines, 4 needle prisms.
void add_materials(gltf::Scene& s, const tree::Tree& tree, const Level& level, const OutputTextures& tex) {
  const tree::Materials& m = tree.materials;
  gltf::Material bark;
  bark.name = "bark";
  bark.base_color = rgba(m.bark_color, 1);
  s.materials.push_back(bark);
  gltf::Material lines;
  lines.name = "bark_lines";
  lines.base_color = rgba(m.bark_color, level.line_alpha);
  lines.alpha_mode = gltf::AlphaMode::kBlend;
  lines.extras = {{"alpha_eq12", level.line_alpha_eq12}};
  s.materials.push_back(lines);
  gltf::Material leaves;
  leaves.name = "leaves";
  leaves.base_color = rgba(m.leaf_color, 1);
  leaves.double_sided = true;
  if (!tex.leaf_png.empty()) {
    s.images.push_back({"leaves.png", "image/png", tex.leaf_png});
    leaves.base_color = {1, 1, 1, 1};
    leaves.base_color_texture.image = 0;
    leaves.base_color_texture.wrap_s = gltf::Wrap::kClampToEdge;
    leaves.base_color_texture.wrap_t = gltf::Wrap::kClampToEdge;
    leaves.alpha_mode = gltf::AlphaMode::kMask;
  }
  s.materials.push_back(leaves);
  gltf::Material needle_lines;
  needle_lines.name = "needle_lines";
  needle_lines.base_color = rgba(m.leaf_color, level.needle_line_alpha);
  needle_lines.extras = {{"alpha_eq12", level.needle_alpha_eq12}};
  needle_lines.alpha_mode = gltf::AlphaMode::kBlend;
  s.materials.push_back(needle_lines);
  gltf::Material needles;
  needles.name = "needles";
  needles.base_color = rgba(m.leaf_color, 1);
  s.materials.push_back(needles);
}

void add_geometry(gltf::Mesh& mesh, const BranchGeometry& g, int tri_material, int line_material) {
  if (!g.tri_indices.empty()) {
    gltf::Primitive p;
    p.mode = gltf::PrimitiveMode::kTriangles;
    p.positions = g.tri_positions;
    p.normals = g.tri_normals;
    p.indices = g.tri_indices;
    p.material = tri_material;
    mesh.primitives.push_back(std::move(p));
  }
  if (!g.line_indices.empty()) {
    gltf::Primitive p;
    p.mode = gltf::PrimitiveMode::kLines;
    p.positions = g.line_positions;
    p.normals = g.line_normals;
    p.indices = g.line_indices;
    p.material = line_material;
    mesh.primitives.push_back(std::move(p));
  }
}

gltf::Mesh level_mesh(const Level& level, std::size_t index, int material_base) {
  gltf::Mesh mesh;
  mesh.name = "lod" + std::to_string(index);
  add_geometry(mesh, level.branches, material_base + 0, material_base + 1);
  if (!level.leaves.indices.empty()) {
    gltf::Primitive p;
    p.positions = level.leaves.positions;
    p.normals = level.leaves.normals;
    p.texcoords = level.leaves.texcoords;
    p.indices = level.leaves.indices;
    p.material = material_base + 2;
    mesh.primitives.push_back(std::move(p));
  }
  add_geometry(mesh, level.needles, material_base + 4, material_base + 3);
  if (mesh.primitives.empty()) {
    // An empty level (no branch survives: impossible with roots kept, but stay valid): one point.
    gltf::Primitive p;
    p.mode = gltf::PrimitiveMode::kPoints;
    p.positions = {0, 0, 0};
    mesh.primitives.push_back(std::move(p));
  }
  mesh.extras = level_extras(level, index);
  return mesh;
}

}  // namespace

double tree_height(const tree::Tree& tree) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& b : tree.branches)
    for (const auto& n : b.nodes) {
      lo = std::min(lo, n.position.y);
      hi = std::max(hi, n.position.y);
    }
  return hi > lo ? hi - lo : 0.0;
}

nlohmann::json level_extras(const Level& level, std::size_t index) {
  const LevelSpec& s = level.spec;
  const LevelCounts& c = level.counts;
  return {{"sylva_lod_level", index},
          {"epsilon_m", s.epsilon},
          {"pixel_error_px", s.delta},
          {"switch_distance_m", s.switch_distance},
          {"E1_m", s.e1},
          {"E2_m", s.e2},
          {"E3_m", s.e3},
          {"E4_m", s.e4},
          {"E5_m", s.e5},
          {"line_alpha", level.line_alpha},
          {"line_alpha_eq12", level.line_alpha_eq12},
          {"needle_line_alpha", level.needle_line_alpha},
          {"needle_line_alpha_eq12", level.needle_alpha_eq12},
          {"max_polygon_error_m", level.branches.max_polygon_error},
          {"counts",
           {{"quads", c.quads},
            {"triangles", c.triangles},
            {"lines", c.lines},
            {"leaves", c.leaves},
            {"needle_lines", c.needle_lines},
            {"needle_quads", c.needle_quads},
            {"internodes", c.internodes},
            {"branches", c.branches}}}};
}

gltf::Scene level_scene(const tree::Tree& tree, const Level& level, std::size_t index, const OutputTextures& tex) {
  gltf::Scene s;
  add_materials(s, tree, level, tex);
  s.meshes.push_back(level_mesh(level, index, 0));
  gltf::Node node;
  node.name = "lod" + std::to_string(index);
  node.mesh = 0;
  node.extras = level_extras(level, index);
  s.nodes.push_back(node);
  s.roots = {0};
  s.extras = {{"sylva_stage", "lod"}, {"tree", tree.name}};
  return s;
}

std::vector<double> screen_coverages(const std::vector<Level>& levels, const Camera& camera, double height) {
  std::vector<double> out;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    if (i + 1 == levels.size()) {
      out.push_back(0.0);
    } else {
      const double d = levels[i + 1].spec.switch_distance;
      out.push_back(height / (2 * d * std::tan(camera.fov_y_rad / 2)));
    }
  }
  return out;
}

std::string encode_chain_glb(const tree::Tree& tree, const std::vector<Level>& levels, const Camera& camera,
                             const OutputTextures& tex) {
  gltf::Scene s;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const int base = static_cast<int>(s.materials.size());
    // Each level has its own alpha, hence its own line materials; the leaf image is shared.
    gltf::Scene tmp;
    add_materials(tmp, tree, levels[i], i == 0 ? tex : OutputTextures{});
    for (auto& m : tmp.materials) {
      if (i > 0 && m.name == "leaves" && !tex.leaf_png.empty()) {
        m.base_color = {1, 1, 1, 1};
        m.base_color_texture.image = 0;
        m.base_color_texture.wrap_s = gltf::Wrap::kClampToEdge;
        m.base_color_texture.wrap_t = gltf::Wrap::kClampToEdge;
        m.alpha_mode = gltf::AlphaMode::kMask;
      }
      m.name += "_lod" + std::to_string(i);
      s.materials.push_back(m);
    }
    if (i == 0) s.images = tmp.images;
    s.meshes.push_back(level_mesh(levels[i], i, base));
    gltf::Node node;
    node.name = "lod" + std::to_string(i);
    node.mesh = static_cast<int>(i);
    node.extras = level_extras(levels[i], i);
    s.nodes.push_back(node);
  }
  const std::vector<double> coverage = screen_coverages(levels, camera, tree_height(tree));
  s.nodes[0].extras["MSFT_screencoverage"] = coverage;
  s.roots = {0};
  s.extras = {{"sylva_stage", "lod"}, {"tree", tree.name}};
  if (levels.size() >= 2) {
    nlohmann::json ids = nlohmann::json::array();
    for (std::size_t i = 1; i < levels.size(); ++i) ids.push_back(i);
    s.nodes[0].extensions = {{"MSFT_lod", {{"ids", ids}}}};
  }
  return gltf::encode(s);
}

nlohmann::json chain_summary(const tree::Tree& tree, const std::vector<Level>& levels, const ChainOptions& o) {
  nlohmann::json j;
  j["tree"] = tree.name;
  j["camera"] = {{"fov_y_deg", o.camera.fov_y_rad * 180 / std::numbers::pi}, {"height_px", o.camera.height_px}};
  j["pixel_error_px"] = o.pixel_error;
  j["tree_height_m"] = tree_height(tree);
  j["source"] = {{"branches", tree.branches.size()}, {"leaves", tree.leaves.size()}, {"needles", tree.needles.size()}};
  const std::vector<double> coverage = screen_coverages(levels, o.camera, tree_height(tree));
  nlohmann::json ls = nlohmann::json::array();
  for (std::size_t i = 0; i < levels.size(); ++i) {
    nlohmann::json l = level_extras(levels[i], i);
    l["file"] = "lod" + std::to_string(i) + ".glb";
    l["screen_coverage"] = coverage[i];
    ls.push_back(l);
  }
  j["levels"] = ls;
  return j;
}

}  // namespace sylva::lod
