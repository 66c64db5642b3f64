// Every species preset through the mesher: the bark is a closed, consistently oriented
// 2-manifold (OpenMesh), genus 0, one component per root, at branch levels 1-3 and subdivision
// 0-2; counts follow from the skeleton; self-intersections are reported; the GLBs validate.
#include <gtest/gtest.h>

#include <cstdio>

#include "libs/gltf/writer.h"
#include "stages/mesh/tests/test_trees.h"
#include "stages/mesh/tree_mesh.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva::mesh {
namespace {

namespace fs = std::filesystem;

std::string name_of(const fs::path& p) { return p.stem().string(); }

std::size_t roots(const tree::Tree& t) {
  std::size_t n = 0;
  for (const auto& b : t.branches) n += b.parent < 0;
  return n;
}

// What every mesh of a tree must satisfy; OpenMesh checks the subdivided mesh again.
void expect_valid(const tree::Tree& t, const TreeMesh& m, int subdivision, const std::string& what) {
  const MeshStats& s = m.stats;
  // The base mesh (mesh_tree checks it too, and throws if it fails).
  EXPECT_TRUE(s.topology.manifold_and_oriented()) << what;
  EXPECT_TRUE(s.topology.closed()) << what;
  EXPECT_EQ(s.topology.components, roots(t)) << what;
  EXPECT_EQ(s.topology.euler, 2 * static_cast<long long>(roots(t))) << what;
  EXPECT_GT(s.topology.signed_volume, 0) << what;
  // Counts: 4 vertices per ring, plus 4 per crotch, inset and backward box; F = V - 2 per
  // component (closed genus 0); each Catmull-Clark level multiplies the smooth quads by 4.
  EXPECT_EQ(s.base_vertices,
            4 * (s.rings + s.joints.split_joints + s.joints.insets + s.joints.backward_fallbacks))
      << what;
  EXPECT_EQ(s.base_quads, s.base_vertices - 2 * roots(t)) << what;
  // At subdivision 1 the flat quads (branches thinner than smooth_radius) stay: a flat quad with
  // k edges split by its smooth neighbours becomes ceil((2 + k) / 2) pieces, 1..3.
  if (s.flat_quads == 0) {
    EXPECT_EQ(s.quads, s.base_quads << (2 * subdivision)) << what;
  } else {
    EXPECT_EQ(subdivision, 1) << what;
    EXPECT_GE(s.quads, 4 * (s.base_quads - s.flat_quads) + s.flat_quads) << what;
    EXPECT_LE(s.quads, 4 * (s.base_quads - s.flat_quads) + 3 * s.flat_quads) << what;
  }
  // The stage's own half-edge check agrees with OpenMesh on the base mesh...
  EXPECT_EQ(s.topology.edges, s.base_quads * 2) << what;
  // ...and OpenMesh checks the subdivided mesh again.
  const TopologyReport r = check_topology(m.bark);
  EXPECT_TRUE(r.manifold_and_oriented() && r.closed())
      << what << ": " << r.refused_faces << " refused, " << r.boundary_edges << " boundary edges";
  EXPECT_EQ(r.euler, 2 * static_cast<long long>(roots(t))) << what;
}

// Young trees at every branch level and subdivision the issue names.
TEST(SpeciesMesh, YoungPresetsAtLevels1To3AndSubdivision0To2) {
  for (const fs::path& preset : test::species_presets()) {
    const tree::Tree& t = test::species_tree(preset, "young");
    for (int level = 1; level <= 3; ++level)
      for (int sub = 0; sub <= 2; ++sub) {
        MeshOptions o;
        o.max_level = level;
        o.subdivision = sub;
        const std::string what = name_of(preset) + "/young max_level " + std::to_string(level) +
                                 " subdivision " + std::to_string(sub);
        const TreeMesh m = mesh_tree(t, o);
        expect_valid(t, m, sub, what);
        // Generated skeletons start every child outside its parent: nothing is dropped.
        EXPECT_EQ(m.stats.skeleton.dropped_branches, 0u) << what;
      }
  }
}

// Adult trees with every level, as the default recipe meshes them (subdivision 1).
TEST(SpeciesMesh, AdultPresetsAtDefaultOptions) {
  for (const fs::path& preset : test::species_presets()) {
    const tree::Tree& t = test::species_tree(preset, "adult");
    const TreeMesh m = mesh_tree(t, MeshOptions{});
    expect_valid(t, m, 1, name_of(preset) + "/adult");
    std::printf(
        "[ stats    ] %s/adult: %zu branches, %zu rings, %zu base quads, %zu quads, joints: %zu ordinary, "
        "%zu split, %zu insets, %zu backward\n",
        name_of(preset).c_str(), m.stats.branches, m.stats.rings, m.stats.base_quads, m.stats.quads,
        m.stats.joints.ordinary_joints, m.stats.joints.split_joints, m.stats.joints.insets,
        m.stats.joints.backward_fallbacks);
  }
}

// The half-edge check the stage runs and OpenMesh's agree (base meshes of the young presets).
TEST(SpeciesMesh, FastTopologyCheckAgreesWithOpenMesh) {
  for (const fs::path& preset : test::species_presets()) {
    MeshOptions o;
    o.subdivision = 0;
    const TreeMesh m = mesh_tree(test::species_tree(preset, "young"), o);
    const TopologyReport fast = check_topology_fast(m.bark), om = check_topology(m.bark);
    EXPECT_EQ(fast.refused_faces, om.refused_faces) << name_of(preset);
    EXPECT_EQ(fast.boundary_edges, om.boundary_edges) << name_of(preset);
    EXPECT_EQ(fast.edges, om.edges) << name_of(preset);
    EXPECT_EQ(fast.euler, om.euler) << name_of(preset);
    EXPECT_EQ(fast.components, om.components) << name_of(preset);
  }
}

// Self-intersections (CGAL) of the base mesh: a statistic, reported, not a failure. Most sit at
// twig tips thinner than min_radius (meshed fatter than they are, so their joints overlap).
TEST(SpeciesMesh, SelfIntersectionsAreReported) {
  for (const fs::path& preset : test::species_presets()) {
    MeshOptions o;
    o.subdivision = 0;
    o.max_level = 2;
    o.count_self_intersections = true;
    const TreeMesh m = mesh_tree(test::species_tree(preset, "young"), o);
    ASSERT_GE(m.stats.self_intersections, 0);
    const double per_1000 =
        1000.0 * static_cast<double>(m.stats.self_intersections) / static_cast<double>(2 * m.stats.quads);
    std::printf(
        "[ stats    ] %s/young max_level 2: %lld self-intersecting triangle pairs (%.2f per 1000 "
        "triangles)\n",
        name_of(preset).c_str(), m.stats.self_intersections, per_1000);
    RecordProperty(name_of(preset) + "_self_intersections", std::to_string(m.stats.self_intersections));
  }
}

// The GLB of every young preset (bark, leaves or needles; untextured here, the stage test adds
// the textures) passes the Khronos validator.
TEST(SpeciesMesh, GlbOfEveryPresetValidates) {
  sylva::test::TempDir dir;
  std::vector<fs::path> files;
  for (const fs::path& preset : test::species_presets()) {
    const tree::Tree& t = test::species_tree(preset, "young");
    MeshOptions o;
    o.max_level = 2;
    const TreeMesh m = mesh_tree(t, o);
    const gltf::Scene scene = make_scene(m, t, {}, {}, {{"statistics", stats_json(m.stats)}});
    files.push_back(dir / (name_of(preset) + ".glb"));
    gltf::write_file(scene, files.back());
    EXPECT_EQ(scene.meshes[0].primitives.size(), 2u) << name_of(preset) << ": bark + leaves or needles";
  }
  for (const auto& r : sylva::test::validate_gltf(files)) {
    if (r.skipped) GTEST_SKIP() << r.skip_reason;
    EXPECT_TRUE(r.ok()) << r.file << ": " << r.tool_error << "\n" << r.report;
  }
}

// Same tree, same options: the same bytes.
TEST(SpeciesMesh, OutputIsDeterministic) {
  const tree::Tree& t = test::species_tree(test::species_presets().front(), "young");
  auto bytes = [&] {
    const TreeMesh m = mesh_tree(t, MeshOptions{});
    return gltf::encode(make_scene(m, t, {}, {}, {{"statistics", stats_json(m.stats)}}));
  };
  EXPECT_EQ(bytes(), bytes());
}

}  // namespace
}  // namespace sylva::mesh
