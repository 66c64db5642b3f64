// glTF output of a LOD chain: per-level primitives, MSFT_lod linking, extras, shared files.
// Seeds: Zhang et al. 2017 §6 (meshes and semi-transparent lines per level); MSFT_lod.
#include "stages/lod/lod_gltf.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>

#include "libs/gltf/writer.h"
#include "libs/lodchain/chain_gltf.h"
#include "libs/sourcegltf/source_scene.h"
#include "libs/tree/default_colors.h"
#include "stages/lod/ribbons.h"

namespace sylva::lod {

namespace {

// The materials of a level, by role; a role a level does not use is left out by the writer.
// Colours are those of the mesh stage (libs/tree/default_colors.h), including its fallbacks
// for trees without colours (an imported TreeQSM tree), and its roughness.
struct LevelMaterials {
  gltf::Material bark, lines, leaves, needle_lines, needles;
};

LevelMaterials level_materials(const tree::Tree& tree, int leaf_image) {
  const tree::Materials& m = tree.materials;
  LevelMaterials out;
  out.bark.name = "bark";
  out.bark.base_color = tree::bark_color(m);
  out.bark.roughness = 0.9f;
  out.lines.name = "bark_lines";
  out.lines.base_color = tree::bark_color(m);  // alpha per vertex (COLOR_0), lines()
  out.lines.roughness = 0.9f;
  out.lines.alpha_mode = gltf::AlphaMode::kBlend;
  out.leaves.name = "leaves";
  out.leaves.base_color = tree::leaf_color(m);
  out.leaves.roughness = 0.7f;
  out.leaves.double_sided = true;
  if (leaf_image >= 0) {
    out.leaves.base_color = {1, 1, 1, 1};
    out.leaves.base_color_texture = {leaf_image, gltf::Wrap::kClampToEdge, gltf::Wrap::kClampToEdge};
    out.leaves.alpha_mode = gltf::AlphaMode::kMask;
  }
  out.needle_lines.name = "needle_lines";
  out.needle_lines.base_color = tree::needle_color(m);
  out.needle_lines.roughness = 0.7f;
  out.needle_lines.alpha_mode = gltf::AlphaMode::kBlend;
  out.needles.name = "needles";
  out.needles.base_color = tree::needle_color(m);
  out.needles.roughness = 0.7f;
  return out;
}

// Adds `m` unless an equal material is there already; returns its index.
int add_material(gltf::Scene& s, const gltf::Material& m) {
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const gltf::Material& o = s.materials[i];
    if (o.name == m.name && o.base_color == m.base_color &&
        o.base_color_texture.image == m.base_color_texture.image && o.alpha_mode == m.alpha_mode &&
        o.double_sided == m.double_sided && o.roughness == m.roughness && o.extras == m.extras)
      return static_cast<int>(i);
  }
  s.materials.push_back(m);
  return static_cast<int>(s.materials.size() - 1);
}

int add_leaf_image(gltf::Scene& s, const OutputTextures& tex) {
  if (tex.leaf_png.empty()) return -1;
  s.images.push_back({lodchain::kLeafImageFile, "image/png", tex.leaf_png, lodchain::kLeafImageFile});
  return static_cast<int>(s.images.size() - 1);
}

gltf::Primitive triangles(const std::vector<float>& positions, const std::vector<float>& normals,
                          const std::vector<std::uint32_t>& indices, int material) {
  gltf::Primitive p;
  p.mode = gltf::PrimitiveMode::kTriangles;
  p.positions = positions;
  p.normals = normals;
  p.indices = indices;
  p.material = material;
  return p;
}

// Lines with each vertex's drawn alpha in COLOR_0 (white, so the material's colour shows):
// eq. (12) per node, as coverage at the switch distance split over the three lines
// (lodmodel::drawn_line_alpha).
gltf::Primitive lines(const BranchGeometry& g, double delta, int material) {
  gltf::Primitive p;
  p.mode = gltf::PrimitiveMode::kLines;
  p.positions = g.line_positions;
  p.normals = g.line_normals;
  p.indices = g.line_indices;
  p.colors.reserve(g.line_alpha12.size() * 4);
  for (float a : g.line_alpha12) {
    p.colors.insert(p.colors.end(),
                    {1.0f, 1.0f, 1.0f, static_cast<float>(lodmodel::drawn_line_alpha(a, delta))});
  }
  p.material = material;
  return p;
}

// The file beside the .gltf files that holds source image `i` (lod_gltf.h).
std::string source_image_file(std::size_t i, const std::string& mime_type) {
  return "source" + std::to_string(i) + (mime_type == "image/jpeg" ? ".jpg" : ".png");
}

// An imported tree's model as the level's mesh: its primitives, materials and images as the
// file had them (libs/sourcegltf), each image a file of its own so the level and chain files
// share it. Its materials are not shared with the reconstruction's: they are the file's own.
gltf::Mesh source_mesh(gltf::Scene& s, const tree::SourceGeometry& g, std::size_t index) {
  const std::size_t first_image = s.images.size();
  sourcegltf::append_source_mesh(s, g, lodchain::level_name(index));
  gltf::Mesh mesh = std::move(s.meshes.back());
  s.meshes.pop_back();
  for (std::size_t i = first_image; i < s.images.size(); ++i)
    s.images[i].uri = source_image_file(i - first_image, s.images[i].mime_type);
  return mesh;
}

// The level's mesh with materials added to `s` (shared when equal). With `ribbon_buffer` >= 0
// the lines become opaque ribbons in that buffer.
gltf::Mesh level_mesh(gltf::Scene& s, const tree::Tree& tree, const Level& level, std::size_t index,
                      int leaf_image, int ribbon_buffer) {
  if (level.source) {
    gltf::Mesh mesh = source_mesh(s, *level.source, index);
    mesh.extras = lodchain::level_extras(level_numbers(level, index));
    return mesh;
  }
  const LevelMaterials mats = level_materials(tree, leaf_image);
  gltf::Mesh mesh;
  mesh.name = lodchain::level_name(index);
  // Opaque and masked triangles first, lines last (lod_gltf.h).
  if (!level.branches.tri_indices.empty())
    mesh.primitives.push_back(triangles(level.branches.tri_positions, level.branches.tri_normals,
                                        level.branches.tri_indices, add_material(s, mats.bark)));
  if (!level.leaves.indices.empty()) {
    gltf::Primitive p = triangles(level.leaves.positions, level.leaves.normals, level.leaves.indices,
                                  add_material(s, mats.leaves));
    p.texcoords = level.leaves.texcoords;
    mesh.primitives.push_back(std::move(p));
  }
  if (!level.needles.tri_indices.empty())
    mesh.primitives.push_back(triangles(level.needles.tri_positions, level.needles.tri_normals,
                                        level.needles.tri_indices, add_material(s, mats.needles)));
  auto add_lines = [&](const BranchGeometry& g, const gltf::Material& line_mat, const gltf::Material& solid) {
    if (g.line_indices.empty()) return;
    if (ribbon_buffer < 0) {
      mesh.primitives.push_back(lines(g, level.spec.delta, add_material(s, line_mat)));
      return;
    }
    const Ribbons r = line_ribbons(g);
    gltf::Primitive p = triangles(r.positions, r.normals, r.indices, add_material(s, solid));
    p.buffer = ribbon_buffer;
    mesh.primitives.push_back(std::move(p));
  };
  add_lines(level.branches, mats.lines, mats.bark);
  add_lines(level.needles, mats.needle_lines, mats.needles);
  if (mesh.primitives.empty()) {
    // An empty level (no branch survives: impossible with roots kept, but stay valid): one point.
    gltf::Primitive p;
    p.mode = gltf::PrimitiveMode::kPoints;
    p.positions = {0, 0, 0};
    mesh.primitives.push_back(std::move(p));
  }
  mesh.extras = lodchain::level_extras(level_numbers(level, index));
  return mesh;
}

nlohmann::json file_extras(const tree::Tree& tree) { return {{"sylva_stage", "lod"}, {"tree", tree.name}}; }

}  // namespace

double tree_height(const tree::Tree& tree) {
  double lo = INFINITY, hi = -INFINITY;
  for (const tree::SourcePrimitive& p : tree.source.primitives)
    for (const tree::Vec3f& v : p.positions) {
      lo = std::min(lo, double(v.y));
      hi = std::max(hi, double(v.y));
    }
  for (const auto& b : tree.branches)
    for (const auto& n : b.nodes) {
      lo = std::min(lo, n.position.y);
      hi = std::max(hi, n.position.y);
    }
  return hi > lo ? hi - lo : 0.0;
}

lodchain::Level level_numbers(const Level& level, std::size_t index) {
  const LevelSpec& s = level.spec;
  const LevelCounts& n = level.counts;
  lodchain::Level l;
  l.sylva_lod_level = index;
  l.epsilon_m = s.epsilon;
  l.pixel_error_px = s.delta;
  l.switch_distance_m = s.switch_distance;
  l.e1_m = s.e1;
  l.e2_m = s.e2;
  l.e3_m = s.e3;
  l.e4_m = s.e4;
  l.e5_m = s.e5;
  l.line_alpha = level.line_alpha;
  l.line_alpha_eq12 = level.line_alpha_eq12;
  l.needle_line_alpha = level.needle_line_alpha;
  l.needle_line_alpha_eq12 = level.needle_alpha_eq12;
  l.max_polygon_error_m = level.branches.max_polygon_error;
  l.counts = {n.quads,        n.triangles,    n.lines,      n.leaves,
              n.needle_lines, n.needle_quads, n.internodes, n.branches};
  return l;
}

bool has_lines(const Level& level) {
  return !level.branches.line_indices.empty() || !level.needles.line_indices.empty();
}

gltf::Scene level_scene(const tree::Tree& tree, const Level& level, std::size_t index,
                        const OutputTextures& tex, bool ribbons) {
  gltf::Scene s;
  const int leaf_image = level.leaves.indices.empty() ? -1 : add_leaf_image(s, tex);
  s.buffer_uris = {lodchain::level_bin(index)};
  const bool with_ribbons = ribbons && has_lines(level);
  if (with_ribbons) s.buffer_uris.push_back(lodchain::ribbons_bin(index));
  s.meshes.push_back(level_mesh(s, tree, level, index, leaf_image, with_ribbons ? 1 : -1));
  if (with_ribbons) {
    // A level of lines only (a leafless tree's coarsest): nothing of lod<i>.bin is used.
    bool uses_level_bin = false;
    for (const gltf::Primitive& p : s.meshes[0].primitives) uses_level_bin |= p.buffer < 0;
    if (!uses_level_bin) {
      s.buffer_uris = {lodchain::ribbons_bin(index)};
      for (gltf::Primitive& p : s.meshes[0].primitives) p.buffer = -1;
    }
  }
  gltf::Node node;
  node.name = lodchain::level_name(index);
  node.mesh = 0;
  node.extras = lodchain::level_extras(level_numbers(level, index));
  s.nodes.push_back(node);
  s.roots = {0};
  s.extras = file_extras(tree);
  return s;
}

double bounding_radius(const Level& l) {
  lodmodel::BoundingBox box;
  if (l.source)
    for (const tree::SourcePrimitive& p : l.source->primitives)
      for (const tree::Vec3f& v : p.positions) box.extend(v.x, v.y, v.z);
  for (const BranchGeometry* g : {&l.branches, &l.needles}) {
    box.extend(g->tri_positions);
    box.extend(g->line_positions);
  }
  box.extend(l.leaves.positions);
  return box.radius();
}

std::vector<double> screen_coverages(const std::vector<Level>& levels, const lodmodel::Camera& camera,
                                     double radius) {
  std::vector<double> out;
  for (std::size_t i = 0; i < levels.size(); ++i)
    out.push_back(i + 1 == levels.size()
                      ? 0.0
                      : lodmodel::screen_coverage(camera, radius, levels[i + 1].spec.switch_distance));
  return out;
}

gltf::Scene chain_scene(const tree::Tree& tree, const std::vector<Level>& levels,
                        const lodmodel::Camera& camera, const OutputTextures& tex) {
  gltf::Scene s;
  bool any_leaves = false;
  for (const Level& l : levels) any_leaves |= !l.leaves.indices.empty();
  const int leaf_image = any_leaves ? add_leaf_image(s, tex) : -1;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    s.buffer_uris.push_back(lodchain::level_bin(i));
    gltf::Mesh mesh = level_mesh(s, tree, levels[i], i, leaf_image, -1);
    mesh.buffer = static_cast<int>(i);
    s.meshes.push_back(std::move(mesh));
    gltf::Node node;
    node.name = lodchain::level_name(i);
    node.mesh = static_cast<int>(i);
    node.extras = lodchain::level_extras(level_numbers(levels[i], i));
    s.nodes.push_back(node);
  }
  std::vector<int> level_nodes(levels.size());
  for (std::size_t i = 0; i < levels.size(); ++i) level_nodes[i] = static_cast<int>(i);
  lodchain::link_levels(s.nodes[0].extras, s.nodes[0].extensions, level_nodes,
                        screen_coverages(levels, camera, bounding_radius(levels[0])));
  s.roots = {0};
  s.extras = file_extras(tree);
  return s;
}

std::string encode_full_detail(const tree::Tree& tree, Level full, const OutputTextures& tex,
                               bool branches_only) {
  if (branches_only) {
    full.leaves = {};
    full.needles = {};
  }
  return gltf::encode(level_scene(tree, full, 0, tex));
}

std::vector<gltf::EncodedFile> encode_chain_files(const tree::Tree& tree, const std::vector<Level>& levels,
                                                  const lodmodel::Camera& camera, const OutputTextures& tex,
                                                  bool ribbons) {
  std::vector<gltf::EncodedFile> out;
  std::map<std::string, std::string> stored;  // name -> bytes of every resource written
  auto keep = [&](const gltf::EncodedFile& f) {
    auto [it, fresh] = stored.emplace(f.name, f.bytes);
    if (fresh) {
      out.push_back(f);
    } else if (it->second != f.bytes) {
      throw std::logic_error("lod output: two files disagree on the bytes of " + f.name);
    }
  };
  // A ribbons file reads the leading non-line part of lod<i>.bin.
  auto check_prefix = [&](const gltf::EncodedFile& f) {
    auto it = stored.find(f.name);
    if (it == stored.end() || it->second.compare(0, f.bytes.size(), f.bytes) != 0)
      throw std::logic_error("lod output: " + f.name + " of a ribbons file is not a prefix of the level's");
  };
  for (std::size_t i = 0; i < levels.size(); ++i) {
    gltf::EncodedFiles level = gltf::encode_external(level_scene(tree, levels[i], i, tex));
    out.push_back({lodchain::level_file(i), std::move(level.gltf)});
    for (const gltf::EncodedFile& f : level.resources) keep(f);
  }
  gltf::EncodedFiles chain = gltf::encode_external(chain_scene(tree, levels, camera, tex));
  out.insert(out.begin(), {lodchain::kChainFile, std::move(chain.gltf)});
  for (const gltf::EncodedFile& f : chain.resources) keep(f);
  if (ribbons)
    for (std::size_t i = 0; i < levels.size(); ++i) {
      if (!has_lines(levels[i])) continue;
      gltf::Scene rs = level_scene(tree, levels[i], i, tex, true);
      // Its buffer 0 is the level's whole lod<i>.bin (lines included): declare the file's size.
      if (rs.buffer_uris.size() == 2) rs.buffer_byte_lengths = {stored.at(lodchain::level_bin(i)).size(), 0};
      gltf::EncodedFiles r = gltf::encode_external(rs);
      out.push_back({lodchain::ribbons_file(i), std::move(r.gltf)});
      for (const gltf::EncodedFile& f : r.resources) {
        if (f.name == lodchain::level_bin(i)) {
          check_prefix(f);
        } else {
          keep(f);
        }
      }
    }
  return out;
}

lodchain::LodChain chain_summary(const tree::Tree& tree, const std::vector<Level>& levels,
                                 const ChainOptions& o, bool ribbons) {
  lodchain::LodChain c;
  c.tree = tree.name;
  c.camera_fov_y_deg = lodmodel::degrees(o.camera.fov_y_rad);
  c.camera_height_px = o.camera.height_px;
  c.pixel_error_px = o.pixel_error;
  c.tree_height_m = tree_height(tree);
  const double radius = levels.empty() ? 0.0 : bounding_radius(levels[0]);
  c.bounding_radius_m = radius;
  c.source = {tree.branches.size(), tree.leaves.size(), tree.needles.size()};
  if (!levels.empty() && levels[0].source) c.source.model_triangles = levels[0].counts.triangles;
  c.chain_file = lodchain::kChainFile;
  const std::vector<double> coverage = screen_coverages(levels, o.camera, radius);
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const Level& level = levels[i];
    lodchain::Level l = level_numbers(level, i);  // the numbers of the extras, plus files and coverage
    l.file = lodchain::level_file(i);
    if (ribbons && has_lines(level)) l.ribbons_file = lodchain::ribbons_file(i);
    l.screen_coverage = coverage[i];
    // Where a loader that switches by MSFT_screencoverage leaves this level for the next one.
    const double d = lodmodel::coverage_distance(o.camera, radius, coverage[i]);
    if (std::isfinite(d)) l.coverage_switch_distance_m = d;
    if (o.card_cluster_px > 0) {
      // How the level's cards were chosen (chain.h CardChoice; docs/stages/lod.md "Card clusters").
      const CardChoice& k = level.cards;
      l.cards = lodchain::CardChoice{k.clustered ? "clusters" : "fsa", k.cut, k.split,
                                     k.measured ? std::optional<double>(k.drift) : std::nullopt, k.rejected};
    }
    c.levels.push_back(std::move(l));
  }
  return c;
}

}  // namespace sylva::lod
