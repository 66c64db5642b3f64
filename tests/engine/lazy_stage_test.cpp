// Lazy stages (pipeline/lazy_stage.h): known by their StageInfo alone until a node of theirs
// runs; then resolved once per run, checked, and forwarded to. A resolver that cannot load the
// implementation fails the node with its message; a no-op never resolves.
#include "pipeline/lazy_stage.h"

#include <gtest/gtest.h>

#include "pipeline/cache.h"
#include "pipeline/executor.h"
#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/fake_filesystem.h"
#include "tests/support/fake_stage_context.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

class FakeModule final : public StageResolver {
 public:
  explicit FakeModule(test::RunLog* log) : real_(log) {}
  const Stage& resolve(std::string_view name) override {
    ++resolves;
    if (!error.empty()) throw StageError(error);
    EXPECT_EQ(name, "text");
    return real_;
  }
  int resolves = 0;
  std::string error;

 private:
  test::TextStage real_;
};

TEST(LazyStageTest, ResolvesOnlyWhenANodeRunsAndReportsLoadErrors) {
  test::RunLog log;
  FakeModule module(&log);
  StageRegistry reg;
  reg.add(make_lazy_stage(test::TextStage(nullptr).info(), module));
  test::TempDir dir;
  test::write_file(dir / "r.yaml",
                   "version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { text: hi }\n");
  RealFileSystem fs;
  Diagnostics d;
  auto recipe = load_recipe(dir / "r.yaml", reg, fs, d);
  ASSERT_TRUE(recipe) << d.str();
  EXPECT_EQ(module.resolves, 0);  // loading and checking need only the info

  SteadyClock clock;
  auto build = [&](const char* cache) {
    Cache c(fs, dir / cache);
    BuildEnv env{fs, c, dir / "out/r", clock, nullptr, nullptr};
    std::string err;
    return run_build(*recipe, env, {}, &err);
  };
  module.error = "cannot load the graphics module /x/libsylva_gfx.so: no such file";
  auto failed = build("cache");
  EXPECT_EQ(failed.nodes.at(0).status, NodeStatus::kFailed);
  EXPECT_EQ(failed.nodes.at(0).error, module.error);
  module.error.clear();
  auto built = build("cache");
  EXPECT_EQ(built.nodes.at(0).status, NodeStatus::kBuilt);
  EXPECT_EQ(log.count("a"), 1);
  EXPECT_EQ(test::read_file(dir / "out/r/a/out.txt"), "hi\n");
  const int after_build = module.resolves;
  EXPECT_EQ(build("cache").nodes.at(0).status, NodeStatus::kCached);
  EXPECT_EQ(module.resolves, after_build);  // a no-op never loads the module
}

TEST(LazyStageTest, AnImplementationOfAnotherVersionIsRefused) {
  FakeModule module(nullptr);
  StageInfo info = test::TextStage(nullptr).info();
  info.version = 2;
  auto lazy = make_lazy_stage(info, module);
  test::FakeFileSystem fake;
  test::FakeStageContext ctx(*lazy, {}, "/out", {}, &fake);
  try {
    lazy->run(ctx);
    FAIL() << "expected logic_error";
  } catch (const std::logic_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "stage 'text' v2 resolved to 'text' v1 (the module comes from another build)");
  }
}

}  // namespace
}  // namespace sylva
