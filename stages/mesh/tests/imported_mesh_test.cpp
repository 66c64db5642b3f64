// The mesh stage on an imported tree (docs/stages/mesh.md "Imported trees"): by default it
// re-meshes the reconstructed skeleton and says so in the GLB's sylva metadata; keep_source
// writes the imported model itself; keep_source on a generated tree and an imported mesh without
// skeleton are refused with exact messages.
#include <gtest/gtest.h>

#include "libs/sourcegltf/testing/sample_source.h"
#include "libs/tree/sylt_format.h"
#include "stages/mesh/mesh_stage.h"
#include "stages/mesh/tests/test_trees.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/gltf_fixtures.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

tree::Tree imported_tree() {
  tree::Tree t = mesh::test::straight_trunk(3);
  t.name = "imported";
  t.source = sourcegltf::testing::strip_and_leaf();
  return t;
}

// Runs the stage on `t` with `keep_source`; returns the GLB's bytes (or throws StageError).
std::string run_mesh(const tree::Tree& t, bool keep_source, const fs::path& out) {
  sylva::test::TempDir in;
  tree::write_sylt(in / "tree.sylt", t);
  const auto stage = make_mesh_stage();
  sylva::test::FakeStageContext ctx(*stage, {{"hier", "tree", in.path()}}, out,
                                    {{"keep_source", Value(keep_source)}});
  stage->run(ctx);
  return sylva::test::read_file(out / "tree.glb");
}

std::string error_of(const tree::Tree& t, bool keep_source) {
  sylva::test::TempDir out;
  try {
    run_mesh(t, keep_source, out.path());
  } catch (const StageError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MeshImported, KeepSourceWritesTheImportedModel) {
  sylva::test::TempDir out;
  const sylva::test::Glb glb = sylva::test::parse_glb(run_mesh(imported_tree(), true, out.path()));
  ASSERT_EQ(glb.json["meshes"].size(), 1u);
  EXPECT_EQ(glb.json["meshes"][0]["primitives"].size(), 2u);
  EXPECT_EQ(glb.json["materials"][1]["name"], "LeafMat");
  EXPECT_EQ(glb.json["asset"]["extras"]["sylva"]["imported_model"],
            "the imported model itself (keep_source)");
  SYLVA_EXPECT_VALID_GLTF(out / "tree.glb");
}

TEST(MeshImported, ByDefaultTheSkeletonIsReMeshedAndTheFileSaysSo) {
  sylva::test::TempDir out;
  const sylva::test::Glb glb = sylva::test::parse_glb(run_mesh(imported_tree(), false, out.path()));
  EXPECT_EQ(glb.json["asset"]["extras"]["sylva"]["imported_model"],
            "re-meshed from the skeleton the hierarchy stage reconstructed; keep_source: true writes the "
            "imported model itself");
  EXPECT_EQ(glb.json["materials"][0]["name"], "bark");
}

TEST(MeshImported, RefusesWhatItCannotDo) {
  tree::Tree generated = mesh::test::straight_trunk(3);
  generated.name = "trunk";
  const std::string keep = error_of(generated, true);
  EXPECT_TRUE(
      keep.ends_with("tree.sylt: keep_source is set, but tree 'trunk' is not an imported mesh (it "
                     "has no source geometry)"))
      << keep;
  tree::Tree no_skeleton = imported_tree();
  no_skeleton.branches.clear();
  EXPECT_EQ(error_of(no_skeleton, false),
            "tree 'imported' has no skeleton: it is an imported mesh; run the hierarchy stage on it first "
            "(docs/stages/hierarchy.md)");
}

}  // namespace
}  // namespace sylva
