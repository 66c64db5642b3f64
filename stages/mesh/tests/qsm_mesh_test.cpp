// Real laser-scanned trees (QSM cylinder tables through the importer): thousands of branches,
// children starting on their parent's axis, mid-segment attachments, backward connections. The
// bark must still be one closed, consistently oriented 2-manifold, and the GLB must validate.
#include <gtest/gtest.h>

#include <cstdio>

#include "libs/gltf/writer.h"
#include "stages/mesh/tests/test_trees.h"
#include "stages/mesh/tree_mesh.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva::mesh {
namespace {

const char* const kFiles[] = {"canopyHydro_5_SmallTree.csv", "canopyHydro_example_tree.csv", "rTwig_QSM.csv",
                              "rTwig_QSM_mat_TreeQSM241_cylinders.tsv"};

TEST(QsmMesh, ImportedTreesMeshToClosedManifolds) {
  sylva::test::TempDir dir;
  std::vector<std::filesystem::path> files;
  for (const char* file : kFiles) {
    const std::optional<tree::Tree> t = test::qsm_tree(file);
    if (!t) GTEST_SKIP() << "no test data (SYLVA_DATA_DIR)";
    for (int sub = 0; sub <= 1; ++sub) {
      MeshOptions o;
      o.subdivision = sub;
      const TreeMesh m = mesh_tree(*t, o);
      const MeshStats& s = m.stats;
      const std::string what = std::string(file) + " subdivision " + std::to_string(sub);
      EXPECT_TRUE(s.topology.manifold_and_oriented() && s.topology.closed()) << what;
      EXPECT_EQ(s.topology.components, 1u) << what;
      EXPECT_EQ(s.topology.euler, 2) << what;
      EXPECT_GT(s.topology.signed_volume, 0) << what;
      // Flat quads (smooth_radius, subdivision 1) stay as 1..3 pieces; the others become 4^sub.
      EXPECT_GE(s.quads, ((s.base_quads - s.flat_quads) << (2 * sub)) + s.flat_quads) << what;
      EXPECT_LE(s.quads, ((s.base_quads - s.flat_quads) << (2 * sub)) + 3 * s.flat_quads) << what;
      const TopologyReport r = check_topology(m.bark);
      EXPECT_TRUE(r.manifold_and_oriented() && r.closed() && r.euler == 2) << what;
      std::printf(
          "[ stats    ] %s: %zu branches, %zu rings, %zu virtual, %zu dropped rings, %zu dropped branches, "
          "%zu moved rings; joints: %zu ordinary, %zu split, %zu insets, %zu backward boxes\n",
          what.c_str(), s.branches, s.rings, s.skeleton.virtual_rings, s.skeleton.dropped_rings,
          s.skeleton.dropped_branches, s.skeleton.pushed_rings, s.joints.ordinary_joints,
          s.joints.split_joints, s.joints.insets, s.joints.backward_fallbacks);
      if (sub == 1) {
        files.push_back(dir / (std::string(file) + ".glb"));
        gltf::write_file(make_scene(m, *t, {}, {}, {{"statistics", stats_json(s)}}), files.back());
      }
    }
  }
  for (const auto& r : sylva::test::validate_gltf(files)) {
    if (r.skipped) GTEST_SKIP() << r.skip_reason;
    EXPECT_TRUE(r.ok()) << r.file << ": " << r.tool_error << "\n" << r.report;
  }
}

// Self-intersections of a real tree's base mesh, reported as a statistic.
TEST(QsmMesh, SelfIntersectionsAreReported) {
  const std::optional<tree::Tree> t = test::qsm_tree("rTwig_QSM.csv");
  if (!t) GTEST_SKIP() << "no test data (SYLVA_DATA_DIR)";
  MeshOptions o;
  o.subdivision = 0;
  o.count_self_intersections = true;
  const TreeMesh m = mesh_tree(*t, o);
  ASSERT_GE(m.stats.self_intersections, 0);
  std::printf("[ stats    ] rTwig_QSM.csv: %lld self-intersecting triangle pairs of %zu\n",
              m.stats.self_intersections, 2 * m.stats.quads);
  RecordProperty("self_intersections", std::to_string(m.stats.self_intersections));
}

}  // namespace
}  // namespace sylva::mesh
