// The mesh stage's core: tree in, bark quad mesh + foliage + glTF scene out. No I/O.
//
// Seed: Nystad 2010 §4.1 step 5 and §4.3 (DAG -> geometry), §5.3 (polygonal mesh), §3.4 and
// §5.5.4; the steps below name the file that implements each.
//
//   1. skeleton   (mesh_skeleton.h)  tree -> rings per branch, children per ring (§4.3.1)
//   2. bark mesh  (box_joints.h)     rings -> one closed quad mesh, box joints (App. D)
//   3. check      (topology_check.h) closed, manifold, consistently oriented (half-edges)
//   4. subdivide  (subdivision.h)    Catmull–Clark 0..3 levels, uvs per §3.4.3
//   5. surface    (surface.h)        normals, tangents, uv seams, triangles
//   6. foliage    (foliage.h)        leaf cards, needles
//   7. scene      (make_scene)       materials, textures, sylva extras -> gltf::Scene
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "libs/gltf/scene.h"
#include "libs/tree/tree.h"
#include "stages/mesh/box_joints.h"
#include "stages/mesh/mesh_skeleton.h"
#include "stages/mesh/quad_mesh.h"
#include "stages/mesh/subdivision.h"
#include "stages/mesh/topology_check.h"

namespace sylva::mesh {

struct MeshOptions {
  int max_level = -1;            // highest branch level meshed (trunk 0); < 0 = all
  int subdivision = 1;           // Catmull–Clark levels, 0..3
  bool open_base = false;        // leave the trunk base open
  bool foliage = true;           // leaf quads (leaves or cards) and needles
  bool mesh_card_twigs = false;  // also mesh the twigs that twig/shoot cards draw
  double min_radius = 0.001;     // m: thinner nodes (tapered tips) are meshed at this radius
  // Ring thinning tolerance as a fraction of the tree's size (the largest extent of its nodes'
  // bounding box; SkeletonOptions::ring_tolerance gets this × size); 0 = keep every ring.
  double ring_tolerance = 0.0005;
  // At subdivision 1: branches thinner at their base than this fraction of the tree's size are
  // left unsubdivided (subdivide_selected; their rings get the square section's corner scale),
  // so Catmull–Clark refines only the trunk and limbs a hero view shows wider than a few pixels.
  // 0 = subdivide every branch; at subdivision >= 2 every branch is subdivided.
  double smooth_radius = 0.0015;
  int bark_repeat = 1;  // bark texture repeats around a branch, 1..16
  Subdivider subdivider = Subdivider::kNative;
  bool count_self_intersections = false;  // CGAL count into the statistics (slow on big trees)
};

struct MeshStats {
  SkeletonStats skeleton;
  JointStats joints;
  TopologyReport topology;  // of the base (unsubdivided) mesh, check_topology_fast
  std::size_t branches = 0, rings = 0;
  std::size_t base_vertices = 0, base_quads = 0;  // before subdivision
  std::size_t quads = 0, vertices = 0;            // after subdivision (quad mesh)
  std::size_t gltf_vertices = 0, triangles = 0;   // bark primitive (seams split)
  std::size_t leaves = 0, needles = 0;            // leaf quads (leaves or cards) and needles written
  std::size_t card_twigs = 0;                     // twigs left to their cards (not meshed)
  double ring_tolerance_m = 0;                    // the thinning tolerance used (m)
  double smooth_radius_m = 0;                     // the smooth/flat radius threshold used (m; 0 = none)
  std::size_t flat_branches = 0;                  // branches left unsubdivided
  std::size_t flat_quads = 0;                     // base quads left unsubdivided
  std::size_t corrected_rings = 0;                // rings whose radius the shrinkage correction changed
  double leaf_area = 0, crown_area = 0, lai = 0;  // libs/tree/foliage.h, of the tree's foliage
  long long self_intersections = -1;              // triangle pairs of the final mesh; -1 = not counted
};

struct TreeMesh {
  QuadMesh bark;                 // after subdivision
  gltf::Primitive bark_surface;  // bark as glTF triangles (material unset)
  gltf::Primitive leaves;        // leaf cards (no vertices when there are none or foliage is off)
  gltf::Primitive needles;       // needles (likewise)
  MeshStats stats;
};

// Steps 1–6. Throws MeshError for a tree that cannot be meshed (empty, invalid) and for the
// internal error of a base mesh that fails the topology check (never expected; reported rather
// than written). Deterministic.
TreeMesh mesh_tree(const tree::Tree& tree, const MeshOptions& options);

// An encoded texture for the scene (PNG or JPEG bytes); empty = none.
struct Texture {
  std::string name;  // e.g. "bark.png"
  std::string bytes;
};

// Step 7: the glTF scene — one node "tree" with one mesh "tree" whose primitives are bark
// (material "bark": baseColor texture or the tree's bark colour, opaque), then, if present,
// leaves (material "leaves": the leaf atlas, alphaMode MASK 0.5, double-sided) and needles
// (material "needles": the leaf colour, opaque). `sylva` is written as asset.extras.sylva.
// Throws MeshError for texture bytes that are neither PNG nor JPEG.
gltf::Scene make_scene(const TreeMesh& mesh, const tree::Tree& tree, const Texture& bark,
                       const Texture& leaves, const nlohmann::json& sylva);

// The statistics as JSON (the `statistics` object of the extras; docs/gltf.md lists the keys).
nlohmann::json stats_json(const MeshStats& stats);

}  // namespace sylva::mesh
