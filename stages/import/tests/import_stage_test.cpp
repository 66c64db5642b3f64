// The adapter: parameters declared, the file read, tree.sylt written; bad input is a
// StageError that names the file and line, with no output declared. All but the real QSM run on
// the in-memory file system: the stage reads and writes only through its context.
#include "stages/import/import_stage.h"

#include <gtest/gtest.h>

#include <set>

#include "libs/tree/stats.h"
#include "libs/tree/sylt_format.h"
#include "stages/import/import_file.h"
#include "tests/support/fake_filesystem.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// The stage's context with its file parameter, on the real disk or (given `fsys`) on the
// in-memory file system.
struct FakeContext : test::FakeStageContext {
  FakeContext(const Stage& stage, const fs::path& file, fs::path out, const Value::Object& overrides = {},
              FileSystem* fsys = nullptr)
      : FakeStageContext(stage, {}, std::move(out), overrides, fsys) {
    name = "imp";
    set_file("file", file);
  }
};

TEST(ImportStage, Declaration) {
  const auto stage = make_import_stage();
  const StageInfo& info = stage->info();
  EXPECT_EQ(info.name, "import");
  EXPECT_EQ(info.output_type, "tree");
  EXPECT_EQ(info.inputs.max, 0);
  std::vector<std::string> names;
  for (const auto& p : info.params) names.push_back(p.name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"file", "format", "columns", "up", "scale", "recenter", "node"}));
  EXPECT_TRUE(info.params[0].required());
  EXPECT_EQ(info.params[1].default_value, Value("auto"));
  EXPECT_EQ(info.params[1].choices,
            (std::vector<std::string>{"auto", "qsm", "treeqsm_txt", "skeleton_txt", "sylt", "gltf", "obj",
                                      "fbx", "dae", "3ds", "ply"}));
  for (const auto& p : info.params) EXPECT_FALSE(p.doc.empty()) << p.name;
  // The key changes with the .sylt format it writes: a cache never serves an older format.
  EXPECT_EQ(info.version % 10, static_cast<int>(tree::kSyltVersion));
  EXPECT_GE(info.version, 32);  // 3: mesh formats and import_report.json
  EXPECT_EQ(info.outputs, (std::vector<std::string>{"tree.sylt", "import_report.json"}));
}

TEST(ImportStage, WritesTreeSylt) {
  const auto data = test::data_dir();
  if (!data) GTEST_SKIP() << "no test data (SYLVA_DATA_DIR)";
  const fs::path file = *data / "qsm" / "rTwig_QSM.csv";
  test::TempDir out;
  const auto stage = make_import_stage();
  FakeContext ctx(*stage, file, out.path());
  stage->run(ctx);
  EXPECT_EQ(ctx.declared, (std::set<std::string>{"tree.sylt", "import_report.json"}));
  const tree::Tree t = tree::read_sylt(out / "tree.sylt");
  EXPECT_EQ(t, import::import_tree(test::read_file(file), file.string(), {}));
  EXPECT_NEAR(tree::compute_stats(t).height, 3.7, 0.1);
}

// Parameters reach the core: scale 1000 (as if the file were in km) and no recentring.
TEST(ImportStage, ParametersApply) {
  test::FakeFileSystem fake;
  fake.put("/t/t.csv",
           "ID,parentID,startX,startY,startZ,endX,endY,endZ,radius\n"
           "0,-1,1,2,3,1,2,4,0.001\n");
  const auto stage = make_import_stage();
  FakeContext ctx(*stage, "/t/t.csv", "/t/out", {{"scale", 1000.0}, {"recenter", false}}, &fake);
  stage->run(ctx);
  const tree::Tree t = tree::decode_sylt(ctx.output("tree.sylt"));
  EXPECT_EQ(t.branches[0].nodes[0].position, (tree::Vec3{1000, 3000, -2000}));
  EXPECT_DOUBLE_EQ(t.branches[0].nodes[0].radius, 1.0);
}

// The stage's error for a file of `content`, on the in-memory file system, with the file's
// directory written "DIR".
std::string stage_error(const std::string& content, const char* name = "bad.csv",
                        Value::Object overrides = {}) {
  test::FakeFileSystem fake;
  const fs::path file = fs::path("/t") / name;
  fake.put(file.string(), content);
  const auto stage = make_import_stage();
  FakeContext ctx(*stage, file, "/t/out", std::move(overrides), &fake);
  try {
    stage->run(ctx);
  } catch (const StageError& e) {
    EXPECT_TRUE(ctx.declared.empty()) << "an output was declared before failing";
    EXPECT_FALSE(fake.stat("/t/out/tree.sylt"));
    const std::string msg = e.what();
    return msg.rfind("/t/", 0) == 0 ? "DIR" + msg.substr(2) : msg;
  }
  return "";
}

constexpr const char* kHead = "ID,parentID,startX,startY,startZ,endX,endY,endZ,radius\n";

// Each bad-input case of the issue, through the stage: exactly one message with file and line.
TEST(ImportStage, BadInputFailsCleanly) {
  const std::string ok_row = "0,-1,0,0,0,0,0,1,0.2\n";
  EXPECT_EQ(stage_error(""), "DIR/bad.csv:1: empty file: nothing to import");
  EXPECT_EQ(stage_error(std::string(kHead) + ok_row + "1,0,0,0,1,nan,0,2,0.1\n"),
            "DIR/bad.csv:3: field 6 (endX): not a finite number: 'nan'");
  EXPECT_EQ(stage_error(std::string(kHead) + ok_row + "1,0,0,0,1,0,0,2,-0.1\n"),
            "DIR/bad.csv:3: field 9 (radius): radius must be > 0, got -0.1");
  EXPECT_EQ(stage_error(std::string(kHead) + ok_row + "1,7,0,0,1,0,0,2,0.1\n"),
            "DIR/bad.csv:3: field 2 (parentID): parent 7 is not the id of any cylinder");
  EXPECT_EQ(stage_error(std::string(kHead) + ok_row + "1,2,0,0,1,0,0,2,0.1\n2,1,0,0,1,0,0,2,0.1\n"),
            "DIR/bad.csv:3: field 2 (parentID): cylinder 1 is in a parent cycle: 1 -> 2 -> 1");
  EXPECT_EQ(stage_error(std::string(kHead) + ok_row + "1,0,0,0,1\n"),
            "DIR/bad.csv:3: truncated row: 5 fields, expected 9");
  EXPECT_EQ(stage_error("a,b,c\n1,2,3\n"),
            "DIR/bad.csv:1: unknown header: none of its 3 names is a recognised QSM column (such "
            "as radius, startX, endX, parentID; see docs/stages/import.md)");
  EXPECT_EQ(stage_error("SYLT but broken", "bad.sylt"), "DIR/bad.sylt: not a .sylt file (bad magic)");
  EXPECT_EQ(stage_error("radius\n1\n", "bad.csv", {{"format", "qsm"}, {"columns", Value::List{"radius"}}}),
            "the columns parameter names the columns of a headerless table: use it with format "
            "treeqsm_txt (or auto), not qsm, whose header names the columns");
}

TEST(ImportStage, MissingFile) {
  test::FakeFileSystem fake;
  const auto stage = make_import_stage();
  FakeContext ctx(*stage, "/t/nope.csv", "/t/out", {}, &fake);
  try {
    stage->run(ctx);
    FAIL() << "no error";
  } catch (const StageError& e) {
    EXPECT_EQ(std::string(e.what()),
              "cannot read '/t/nope.csv' (parameter 'file'): No such file or directory");
  }
}

// A mesh (an OBJ on the in-memory file system) writes tree.sylt and an import report with its
// warnings (the file by its name) and facts; `up` and `scale` reach the mesh reader.
TEST(ImportStage, MeshWritesReport) {
  test::FakeFileSystem fake;
  fake.put("/t/tree.obj", "v 0 0 0\nv 1 0 0\nv 1 0 2\nv 0 0 2\nf 1 2 3 4\n");
  const auto stage = make_import_stage();
  FakeContext ctx(*stage, "/t/tree.obj", "/t/out", {{"up", "z"}, {"scale", 2.0}}, &fake);
  stage->run(ctx);
  EXPECT_EQ(ctx.declared, (std::set<std::string>{"tree.sylt", "import_report.json"}));
  EXPECT_EQ(ctx.output("import_report.json"),
            "{\n"
            "  \"file\": \"tree.obj\",\n"
            "  \"format\": \"obj\",\n"
            "  \"mesh\": {\n"
            "    \"height_m\": 4.0,\n"
            "    \"images\": 0,\n"
            "    \"materials\": 1,\n"
            "    \"primitives\": 1,\n"
            "    \"triangles\": 2,\n"
            "    \"unit\": \"m\",\n"
            "    \"unit_scale\": 1.0,\n"
            "    \"up_axis\": \"z\",\n"
            "    \"vertices\": 4\n"
            "  },\n"
            "  \"warnings\": [\n"
            "    \"tree.obj: warning: 1 quad(s) and 0 polygon(s) of more than 4 sides triangulated\"\n"
            "  ]\n"
            "}\n");
}

// Non-mesh formats write the report too (no warnings), so the output list is fixed.
TEST(ImportStage, QsmWritesEmptyReport) {
  test::FakeFileSystem fake;
  fake.put("/t/t.csv",
           "ID,parentID,startX,startY,startZ,endX,endY,endZ,radius\n"
           "0,-1,1,2,3,1,2,4,0.001\n");
  const auto stage = make_import_stage();
  FakeContext ctx(*stage, "/t/t.csv", "/t/out", {}, &fake);
  stage->run(ctx);
  EXPECT_EQ(ctx.output("import_report.json"),
            "{\n  \"file\": \"t.csv\",\n  \"format\": \"qsm\",\n  \"warnings\": []\n}\n");
  // up: auto is z for a QSM table, as before.
  EXPECT_EQ(tree::decode_sylt(ctx.output("tree.sylt")).branches[0].nodes[1].position, (tree::Vec3{0, 1, 0}));
}

// A mesh the reader refuses is a StageError naming the file; nothing is declared.
TEST(ImportStage, BadMeshIsStageError) {
  test::FakeFileSystem fake;
  fake.put("/t/bad.glb", "glTFxxxx");
  const auto stage = make_import_stage();
  FakeContext ctx(*stage, "/t/bad.glb", "/t/out", {}, &fake);
  try {
    stage->run(ctx);
    FAIL() << "no error";
  } catch (const StageError& e) {
    EXPECT_STREQ(e.what(), "/t/bad.glb: error: invalid glTF: Too short data size for glTF Binary.");
  }
  EXPECT_TRUE(ctx.declared.empty());
}

}  // namespace
}  // namespace sylva
