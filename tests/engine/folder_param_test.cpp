// A path parameter declared with_folder_for() (pipeline/param.h): a model file whose extension
// is listed brings its whole folder into the node's key and its files() allow list; other
// extensions behave as a plain path. On the in-memory file system (tests/support).
#include <gtest/gtest.h>

#include "pipeline/cache.h"
#include "pipeline/executor.h"
#include "pipeline/param.h"
#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/fake_filesystem.h"

namespace sylva {
namespace {

constexpr std::int64_t kMs = 1000000;

class FolderParamTest : public ::testing::Test {
 protected:
  FolderParamTest() { test::register_test_stages(reg_, &log_); }

  // Puts `path` with `bytes`, a millisecond later than the last (so a change is seen by stat).
  void put(const std::string& path, const std::string& bytes) {
    fs_.now += kMs;
    fs_.put(path, bytes);
    fs_.now += kMs;
  }

  Recipe load(const std::string& file, const std::string& sibling = "") {
    fs_.put("/p/r.yaml", "version: 1\nname: r\nnodes:\n  m:\n    stage: readmodel\n    with: { file: " +
                             file + (sibling.empty() ? "" : ", sibling: " + sibling) + " }\n");
    Diagnostics d;
    auto r = load_recipe("/p/r.yaml", reg_, fs_, d);
    EXPECT_TRUE(r) << d.str();
    return *r;
  }

  BuildSummary build(const Recipe& r) {
    Cache cache(fs_, "/c");
    BuildEnv env{fs_, cache, "/o/r", clock_, nullptr, nullptr};
    std::string err;
    auto s = run_build(r, env, {}, &err);
    EXPECT_EQ(err, "");
    return s;
  }

  // Builds, then returns the status of node m.
  NodeStatus status(const Recipe& r, std::string* error = nullptr) {
    auto s = build(r);
    if (error) *error = s.nodes.at(0).error;
    return s.nodes.at(0).status;
  }

  StageRegistry reg_;
  test::RunLog log_;
  test::FakeFileSystem fs_;
  SteadyClock clock_;
};

TEST(FolderParam, ExtensionMatchesWithoutRegardToCase) {
  const ParamSpec spec = Param::path("file").with_folder_for({".gltf", ".OBJ"});
  EXPECT_EQ(param_folder(spec, "/p/m/tree.gltf"), std::filesystem::path("/p/m"));
  EXPECT_EQ(param_folder(spec, "/p/m/tree.GLTF"), std::filesystem::path("/p/m"));
  EXPECT_EQ(param_folder(spec, "/p/m/tree.obj"), std::filesystem::path("/p/m"));
  EXPECT_EQ(param_folder(spec, "/p/m/tree.csv"), std::nullopt);
  EXPECT_EQ(param_folder(spec, "/p/m/gltf"), std::nullopt);
  EXPECT_EQ(param_folder(Param::path("file"), "/p/m/tree.gltf"), std::nullopt);
}

// Editing the .bin beside a .gltf (or a texture in a subfolder) re-runs the node; a build with
// nothing changed is cached.
TEST_F(FolderParamTest, ChangingASiblingOfAModelRebuilds) {
  put("/p/m/tree.gltf", "{gltf}");
  put("/p/m/tree.bin", "bin1");
  put("/p/m/tex/bark.png", "png1");
  Recipe r = load("m/tree.gltf");
  EXPECT_EQ(status(r), NodeStatus::kBuilt);
  EXPECT_EQ(status(load("m/tree.gltf")), NodeStatus::kCached);
  put("/p/m/tree.bin", "bin2");
  EXPECT_EQ(status(load("m/tree.gltf")), NodeStatus::kBuilt);
  put("/p/m/tex/bark.png", "png2");
  EXPECT_EQ(status(load("m/tree.gltf")), NodeStatus::kBuilt);
  put("/p/m/tex/new.png", "png");  // a new file in the folder counts too
  EXPECT_EQ(status(load("m/tree.gltf")), NodeStatus::kBuilt);
  EXPECT_EQ(log_.count("m"), 4);
  // A file outside the folder does not.
  put("/p/other.txt", "x");
  EXPECT_EQ(status(load("m/tree.gltf")), NodeStatus::kCached);
}

// A .csv has no folder: its neighbours are not part of the node's input.
TEST_F(FolderParamTest, ChangingASiblingOfACsvDoesNotRebuild) {
  put("/p/q/tree.csv", "1,2,3");
  put("/p/q/notes.txt", "a");
  EXPECT_EQ(status(load("q/tree.csv")), NodeStatus::kBuilt);
  put("/p/q/notes.txt", "b");
  EXPECT_EQ(status(load("q/tree.csv")), NodeStatus::kCached);
  put("/p/q/tree.csv", "4,5,6");
  EXPECT_EQ(status(load("q/tree.csv")), NodeStatus::kBuilt);
}

// The stage reads a sibling (and a file in a subfolder) through ctx.files().
TEST_F(FolderParamTest, FilesReadsASibling) {
  put("/p/m/tree.gltf", "G;");
  put("/p/m/tree.bin", "B");
  put("/p/m/tex/bark.png", "P");
  EXPECT_EQ(status(load("m/tree.gltf", "tree.bin")), NodeStatus::kBuilt);
  EXPECT_EQ(fs_.files.at("/o/r/m/out.txt"), "G;B");
  EXPECT_EQ(status(load("m/tree.gltf", "tex/bark.png")), NodeStatus::kBuilt);
  EXPECT_EQ(fs_.files.at("/o/r/m/out.txt"), "G;P");
}

// Outside the folder, and beside a .csv, reading is refused (the file is not in the key).
TEST_F(FolderParamTest, ReadingOutsideIsRefused) {
  put("/p/m/tree.gltf", "G;");
  put("/p/secret.txt", "S");
  put("/p/q/tree.csv", "1");
  put("/p/q/notes.txt", "N");
  std::string error;
  EXPECT_EQ(status(load("m/tree.gltf", "../secret.txt"), &error), NodeStatus::kFailed);
  EXPECT_NE(error.find("the stage read '/p/m/../secret.txt', which is not one of its declared inputs"),
            std::string::npos)
      << error;
  EXPECT_EQ(status(load("q/tree.csv", "notes.txt"), &error), NodeStatus::kFailed);
  EXPECT_NE(error.find("the stage read '/p/q/notes.txt', which is not one of its declared inputs"),
            std::string::npos)
      << error;
}

// A model in a folder of more than kMaxFolderFiles files is a recipe error at the parameter;
// at the limit it builds. A file added after loading is caught when the key is computed, before
// anything in the folder is hashed.
TEST_F(FolderParamTest, FolderOverTheLimitIsRefused) {
  put("/p/tree.gltf", "G");
  for (std::size_t i = 1; i < kMaxFolderFiles - 1; ++i) fs_.put("/p/d/f" + std::to_string(i), "x");
  // The folder /p holds r.yaml, tree.gltf and the files above: kMaxFolderFiles in all.
  Recipe r = load("tree.gltf");
  EXPECT_EQ(status(r), NodeStatus::kBuilt);
  fs_.put("/p/d/one_more", "x");
  fs_.reads.clear();
  std::string error;
  EXPECT_EQ(status(r, &error), NodeStatus::kFailed);
  EXPECT_EQ(error,
            "cannot read the folder '/p' of '/p/tree.gltf' (parameter 'file'): holds more than 2000 files; a "
            ".gltf file brings its whole folder into the node's key: give the model a folder of its own");
  for (const std::string& read : fs_.reads) EXPECT_NE(read.rfind("/p/d/", 0), 0u) << read;  // nothing hashed
  Diagnostics d;
  EXPECT_FALSE(load_recipe("/p/r.yaml", reg_, fs_, d));
  EXPECT_EQ(
      d.str().substr(0, d.str().find('\n')),
      "/p/r.yaml:6:19: error: parameter 'file': the folder '/p' of this .gltf file holds more than 2000 "
      "files, and a model's whole folder enters the node's key: give the model a folder of its own");
}

}  // namespace
}  // namespace sylva
