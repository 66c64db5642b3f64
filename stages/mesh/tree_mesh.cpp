// The mesh stage's core as a sequence of named passes (tree_mesh.h lists them).
// Seed: Nystad 2010 §4.1 step 5, §4.3, §5.3; §5.5.4 for foliage.
#include "stages/mesh/tree_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "libs/tree/default_colors.h"
#include "libs/tree/foliage.h"
#include "stages/mesh/foliage.h"
#include "stages/mesh/surface.h"

namespace sylva::mesh {
namespace {

std::string mime_type(const Texture& t) {
  const std::string& b = t.bytes;
  if (b.size() >= 8 && b.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0) return "image/png";
  if (b.size() >= 3 && static_cast<unsigned char>(b[0]) == 0xFF && static_cast<unsigned char>(b[1]) == 0xD8 &&
      static_cast<unsigned char>(b[2]) == 0xFF)
    return "image/jpeg";
  throw MeshError("texture '" + t.name + "' is neither a PNG nor a JPEG file");
}

// COLOR_0 = the tint below bark_tint_from_m (above the first root's base), white above
// bark_tint_to_m, smoothstep between; nothing when the tint is white or the heights are equal.
void apply_bark_tint(const tree::Tree& tree, gltf::Primitive& p) {
  const tree::Materials& m = tree.materials;
  const bool white = m.bark_tint.r == 1 && m.bark_tint.g == 1 && m.bark_tint.b == 1;
  if (white || !(m.bark_tint_to_m > m.bark_tint_from_m) || tree.branches.empty()) return;
  const double base = tree.branches.front().nodes.front().position.y;
  const std::size_t n = p.vertex_count();
  p.colors.resize(4 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const double h = p.positions[3 * i + 1] - base;
    double t = std::clamp((h - m.bark_tint_from_m) / (m.bark_tint_to_m - m.bark_tint_from_m), 0.0, 1.0);
    t = t * t * (3 - 2 * t);
    p.colors[4 * i] = static_cast<float>(m.bark_tint.r + (1 - m.bark_tint.r) * t);
    p.colors[4 * i + 1] = static_cast<float>(m.bark_tint.g + (1 - m.bark_tint.g) * t);
    p.colors[4 * i + 2] = static_cast<float>(m.bark_tint.b + (1 - m.bark_tint.b) * t);
    p.colors[4 * i + 3] = 1.0f;
  }
}

// Catmull–Clark shrinks a straight tube's square section by the same factor everywhere (its
// corners move to 3/4 of their distance in the first step; corner_scale undoes that), but near a
// joint — box faces, bridges to children, inset rims — the section shrinks less (or more), and
// the bark swells (or thins) there. One correction: the first step's vertex points of every
// ring's corners are computed on the base mesh; a ring whose corners end farther out than a
// straight tube's (ratio rho to 3/4, clamped to [0.8, 1.25]) gets its radius divided by
// rho^0.5 — joints interact, a full step overshoots — and the mesh is built again from the
// corrected rings; rings that thin out are left (a real taper step). Returns the rings changed.
constexpr double kShrinkGain = 0.5;  // a square-root step: joints interact, a full step overshoots

std::size_t correct_ring_shrinkage(MeshSkeleton& sk, const QuadMesh& base,
                                   const std::vector<std::vector<std::uint32_t>>& ring_vertices) {
  const std::size_t nv = base.positions.size();
  std::vector<Vec3> fsum(nv, Vec3{}), nsum(nv, Vec3{});
  std::vector<std::uint32_t> valence(nv, 0);
  for (const Quad& q : base.quads) {
    const Vec3 f =
        (base.positions[q[0]] + base.positions[q[1]] + base.positions[q[2]] + base.positions[q[3]]) * 0.25;
    for (std::size_t i = 0; i < 4; ++i) {
      fsum[q[i]] += f;
      nsum[q[i]] += base.positions[q[(i + 1) % 4]] + base.positions[q[(i + 3) % 4]];
      ++valence[q[i]];
    }
  }
  auto vertex_point = [&](std::uint32_t v) {
    const double n = valence[v];
    const Vec3 favg = fsum[v] / n, navg = nsum[v] / (2 * n);
    const Vec3 ravg = (base.positions[v] + navg) * 0.5;
    return (favg + ravg * 2.0 + base.positions[v] * (n - 3)) / n;
  };
  std::size_t corrected = 0;
  for (std::size_t b = 0; b < sk.branches.size(); ++b) {
    if (!sk.branches[b].smooth) continue;  // not subdivided: nothing shrinks
    for (std::size_t r = 0; r < sk.branches[b].rings.size(); ++r) {
      const std::uint32_t first = r < ring_vertices[b].size() ? ring_vertices[b][r] : 0xFFFFFFFFu;
      if (first == 0xFFFFFFFFu || first + 3 >= nv) continue;
      if (!base.crease.empty() && base.crease[first]) continue;  // the creased foot is exact
      Ring& g = sk.branches[b].rings[r];
      double before = 0, after = 0;
      for (std::uint32_t j = 0; j < 4; ++j) {
        if (valence[first + j] < 3) continue;
        auto perp = [&](Vec3 d) { return tree::length(d - g.frame.t * tree::dot(d, g.frame.t)); };
        before += perp(base.positions[first + j] - g.center);
        after += perp(vertex_point(first + j) - g.center);
      }
      if (!(before > 0)) continue;
      const double rho = after / before / 0.75;
      if (rho < 1.01) continue;  // only swelling is corrected (a thinning ring is a real taper step)
      g.radius = std::max(1e-6, g.radius / std::pow(std::clamp(rho, 0.8, 1.25), kShrinkGain));
      ++corrected;
    }
  }
  return corrected;
}

// The largest extent of the bounding box of the tree's nodes (m): the size the relative
// tolerances of MeshOptions refer to.
double tree_size(const tree::Tree& tree) {
  if (tree.branches.empty()) return 0;
  Vec3 lo = tree.branches[0].nodes[0].position, hi = lo;
  for (const tree::Branch& b : tree.branches)
    for (const tree::Node& nd : b.nodes) {
      lo = {std::min(lo.x, nd.position.x), std::min(lo.y, nd.position.y), std::min(lo.z, nd.position.z)};
      hi = {std::max(hi.x, nd.position.x), std::max(hi.y, nd.position.y), std::max(hi.z, nd.position.z)};
    }
  return std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
}

}  // namespace

TreeMesh mesh_tree(const tree::Tree& tree, const MeshOptions& options) {
  TreeMesh out;
  MeshStats& st = out.stats;
  const int levels = std::clamp(options.subdivision, 0, 3);
  const double corner_scale = corner_scale_for_subdivision(levels);

  // 1. Skeleton.
  SkeletonOptions so;
  so.max_level = options.max_level;
  so.min_radius = options.min_radius;
  so.corner_scale = corner_scale;
  so.compensate_smoothing = levels > 0;
  if (options.ring_tolerance > 0) {
    so.ring_tolerance = options.ring_tolerance * tree_size(tree);
    st.ring_tolerance_m = so.ring_tolerance;
  }
  if (options.smooth_radius > 0 && levels == 1) {
    so.smooth_min_radius = options.smooth_radius * tree_size(tree);
    so.rough_scale = corner_scale_for_subdivision(0) / corner_scale;
    st.smooth_radius_m = so.smooth_min_radius;
  }
  if (options.foliage && !options.mesh_card_twigs) {
    so.omit = tree::twigs_drawn_by_cards(tree);
    for (char c : so.omit) st.card_twigs += c ? 1 : 0;
  }
  MeshSkeleton skeleton = build_skeleton(tree, so);
  st.skeleton = skeleton.stats;
  st.branches = skeleton.branches.size();
  st.rings = skeleton.ring_count();

  // 2. Bark mesh with box joints.
  BarkOptions bo;
  bo.open_base = options.open_base;
  bo.corner_scale = corner_scale;
  bo.bark_repeat = std::clamp(options.bark_repeat, 1, 16);
  std::vector<std::vector<std::uint32_t>> ring_vertices;
  QuadMesh base = build_bark_mesh(skeleton, bo, &st.joints, &ring_vertices);
  if (levels > 0) {
    st.corrected_rings = correct_ring_shrinkage(skeleton, base, ring_vertices);
    if (st.corrected_rings > 0) {
      st.joints = {};
      base = build_bark_mesh(skeleton, bo, &st.joints, &ring_vertices);
    }
  }
  // Smooth quads: those with no corner on a ring of a flat branch.
  std::vector<std::uint8_t> smooth;
  if (so.smooth_min_radius > 0) {
    std::vector<std::uint8_t> flat_vertex(base.vertex_count(), 0);
    for (std::size_t b = 0; b < skeleton.branches.size(); ++b) {
      if (skeleton.branches[b].smooth) continue;
      ++st.flat_branches;
      for (std::uint32_t first : ring_vertices[b])
        for (std::uint32_t j = 0; j < 4 && first + j < flat_vertex.size(); ++j) flat_vertex[first + j] = 1;
    }
    smooth.assign(base.quad_count(), 1);
    for (std::size_t f = 0; f < base.quad_count(); ++f)
      for (std::uint32_t v : base.quads[f])
        if (flat_vertex[v]) smooth[f] = 0;
    for (std::uint8_t s : smooth) st.flat_quads += s ? 0 : 1;
  }
  st.base_vertices = base.vertex_count();
  st.base_quads = base.quad_count();

  // 3. Topology check: closed (except the open base), manifold, consistently oriented.
  st.topology = check_topology_fast(base);
  const std::size_t open_edges = options.open_base ? 4 * st.joints.components : 0;
  if (!st.topology.manifold_and_oriented() || st.topology.boundary_edges != open_edges)
    throw MeshError("internal error: the bark mesh is not a closed, consistently oriented 2-manifold (" +
                    std::to_string(st.topology.refused_faces) + " quads refused, " +
                    std::to_string(st.topology.boundary_edges) + " boundary edges); please report this tree");

  // 4. Subdivision.
  out.bark = smooth.empty() ? subdivide(base, levels, options.subdivider) : subdivide_selected(base, smooth);
  st.quads = out.bark.quad_count();
  st.vertices = out.bark.vertex_count();
  if (options.count_self_intersections)
    st.self_intersections = static_cast<long long>(count_self_intersections(out.bark));

  // 5. Surface for glTF, with the bark tint (libs/tree Materials) as vertex colours.
  out.bark_surface = to_primitive(out.bark);
  apply_bark_tint(tree, out.bark_surface);
  st.gltf_vertices = out.bark_surface.vertex_count();
  st.triangles = out.bark_surface.indices.size() / 3;

  // 6. Foliage.
  if (options.foliage) {
    out.leaves = leaf_cards(tree);
    out.needles = needle_geometry(tree);
    st.leaves = tree.leaves.size();
    st.needles = tree.needles.size();
    const tree::CrownFoliage crown = tree::crown_foliage(tree);
    st.leaf_area = crown.leaf_area;
    st.crown_area = crown.crown_area;
    st.lai = crown.lai();
  }
  return out;
}

gltf::Scene make_scene(const TreeMesh& mesh, const tree::Tree& tree, const Texture& bark,
                       const Texture& leaves, const nlohmann::json& sylva) {
  gltf::Scene s;
  auto add_image = [&](const Texture& t) {
    if (t.bytes.empty()) return -1;
    s.images.push_back({t.name, mime_type(t), t.bytes, ""});
    return static_cast<int>(s.images.size() - 1);
  };
  const int bark_image = add_image(bark);

  gltf::Mesh m;
  m.name = "tree";
  // Bark.
  {
    gltf::Material mat;
    mat.name = "bark";
    mat.roughness = 0.9f;
    if (bark_image >= 0) {
      mat.base_color_texture.image = bark_image;
    } else {
      mat.base_color = tree::bark_color(tree.materials);
    }
    s.materials.push_back(mat);
    gltf::Primitive p = mesh.bark_surface;
    p.material = 0;
    m.primitives.push_back(std::move(p));
  }
  // Leaf cards.
  if (!mesh.leaves.positions.empty()) {
    const int leaf_image = add_image(leaves);
    gltf::Material mat;
    mat.name = "leaves";
    mat.roughness = 0.7f;
    mat.alpha_mode = gltf::AlphaMode::kMask;
    mat.alpha_cutoff = 0.5f;
    mat.double_sided = true;
    if (leaf_image >= 0) {
      mat.base_color_texture = {leaf_image, gltf::Wrap::kClampToEdge, gltf::Wrap::kClampToEdge};
    } else {
      mat.base_color = tree::leaf_color(tree.materials);
    }
    s.materials.push_back(mat);
    gltf::Primitive p = mesh.leaves;
    p.material = static_cast<int>(s.materials.size() - 1);
    m.primitives.push_back(std::move(p));
  }
  // Needles.
  if (!mesh.needles.positions.empty()) {
    gltf::Material mat;
    mat.name = "needles";
    mat.roughness = 0.7f;
    mat.base_color = tree::needle_color(tree.materials);
    s.materials.push_back(mat);
    gltf::Primitive p = mesh.needles;
    p.material = static_cast<int>(s.materials.size() - 1);
    m.primitives.push_back(std::move(p));
  }
  s.meshes.push_back(std::move(m));
  gltf::Node node;
  node.name = "tree";
  node.mesh = 0;
  s.nodes.push_back(node);
  s.roots = {0};
  s.generator = "sylva";
  if (!sylva.is_null()) s.extras = {{"sylva", sylva}};
  return s;
}

nlohmann::json stats_json(const MeshStats& st) {
  nlohmann::json j;
  j["branches"] = st.branches;
  j["rings"] = st.rings;
  j["base_vertices"] = st.base_vertices;
  j["base_quads"] = st.base_quads;
  j["quads"] = st.quads;
  j["vertices"] = st.vertices;
  j["gltf_vertices"] = st.gltf_vertices;
  j["triangles"] = st.triangles;
  j["leaves"] = st.leaves;
  j["needles"] = st.needles;
  j["card_twigs"] = st.card_twigs;
  j["leaf_area_m2"] = st.leaf_area;
  j["crown_area_m2"] = st.crown_area;
  j["lai"] = st.lai;
  j["components"] = st.topology.components;
  j["euler_characteristic"] = st.topology.euler;
  j["joints"] = {{"bridges", st.joints.bridges},
                 {"ordinary", st.joints.ordinary_joints},
                 {"equal_split", st.joints.split_joints},
                 {"recursive_sides", st.joints.recursive_sides},
                 {"backward_fallbacks", st.joints.backward_fallbacks},
                 {"insets", st.joints.insets},
                 {"tip_caps", st.joints.tip_caps},
                 {"base_caps", st.joints.base_caps}};
  j["skeleton"] = {{"virtual_rings", st.skeleton.virtual_rings},
                   {"collapsed_junctions", st.skeleton.collapsed_junctions},
                   {"merged_rings", st.skeleton.merged_rings},
                   {"clamped_radii", st.skeleton.clamped_radii},
                   {"dropped_rings", st.skeleton.dropped_rings},
                   {"pushed_rings", st.skeleton.pushed_rings},
                   {"dropped_branches", st.skeleton.dropped_branches},
                   {"thinned_rings", st.skeleton.thinned_rings}};
  j["ring_tolerance_m"] = st.ring_tolerance_m;
  j["smooth_radius_m"] = st.smooth_radius_m;
  j["flat_branches"] = st.flat_branches;
  j["flat_quads"] = st.flat_quads;
  if (st.self_intersections >= 0) j["self_intersections"] = st.self_intersections;
  return j;
}

}  // namespace sylva::mesh
