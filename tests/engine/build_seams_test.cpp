// The build loop through its seams (docs/architecture.md, "Engine seams"), each replaced by a
// fake: the cache by an in-memory ActionCache + BlobStore (tests/support/fake_cache.h), the
// runner by one that records its jobs, the disk by the in-memory file system. What a remote
// cache and a cluster executor will rely on: results and outputs move only through the seams.
#include <gtest/gtest.h>

#include <algorithm>
#include <mutex>

#include "pipeline/cache.h"
#include "pipeline/executor.h"
#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/fake_cache.h"
#include "tests/support/fake_filesystem.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// A NodeRunner that runs nothing itself: it records each job and stores "<node>:" followed by
// its inputs' bytes as the node's one output, out.txt, in the blob store.
class RecordingRunner final : public NodeRunner {
 public:
  RecordingRunner(FileSystem& fs, BlobStore& blobs) : fs_(fs), blobs_(blobs) {}
  NodeRun run(const NodeJob& job) override {
    std::string bytes = job.node.name + ":";
    for (const auto& in : job.inputs)
      for (const auto& f : in.files) bytes += fs_.read(f.path).value_or("?");
    const fs::path scratch = "/scratch/" + job.node.name;
    fs_.write_atomic(scratch, bytes, false);
    NodeRun run;
    run.executed = true;
    run.result.outputs.push_back({"out.txt", *blobs_.put_file(scratch, nullptr, false)});
    std::lock_guard l(mu_);
    jobs.push_back(job.node.name + " <- " + std::to_string(job.inputs.size()) + " input(s), key " +
                   job.key.substr(0, 8));
    return run;
  }
  std::vector<std::string> jobs;

 private:
  FileSystem& fs_;
  BlobStore& blobs_;
  std::mutex mu_;
};

class BuildSeamsTest : public ::testing::Test {
 protected:
  BuildSeamsTest() { test::register_test_stages(reg_, &log_); }

  Recipe load(const std::string& yaml) {
    fs_.put("/p/r.yaml", yaml);
    Diagnostics d;
    auto r = load_recipe("/p/r.yaml", reg_, fs_, d);
    EXPECT_TRUE(r) << d.str();
    return r ? *r : Recipe{};
  }
  // A build into out dir `out` whose results and blobs go to `remote` (the local Cache only
  // provides locks and scratch directories), run by `runner` (nullptr: the stages, locally).
  BuildSummary build(const Recipe& r, const fs::path& out, NodeRunner* runner = nullptr,
                     BuildOptions o = {}) {
    Cache local(fs_, "/local-cache");
    BuildEnv env{fs_, local, out / r.name, clock_, nullptr, nullptr, &remote_, &remote_, runner};
    std::string err;
    auto s = run_build(r, env, o, &err);
    EXPECT_EQ(err, "");
    return s;
  }

  test::FakeFileSystem fs_;
  test::FakeCache remote_{fs_};
  StageRegistry reg_;
  test::RunLog log_;
  SteadyClock clock_;
};

const char* kRecipe =
    "version: 1\nname: r\nnodes:\n"
    "  a:\n    stage: text\n    with: { text: A }\n"
    "  b:\n    stage: text\n    with: { text: B }\n"
    "  ab:\n    stage: concat\n    needs: [a, b]\n";

// Two machines (two out dirs) sharing one cache: the second downloads every result and runs
// nothing; nothing goes to the local cache's store.
TEST_F(BuildSeamsTest, ASecondOutDirSharingTheCacheRunsNothing) {
  const Recipe r = load(kRecipe);
  auto first = build(r, "/machine1");
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first.count(NodeStatus::kBuilt), 3u);
  EXPECT_EQ(remote_.results.size(), 3u);
  EXPECT_EQ(remote_.blobs.size(), 3u);
  EXPECT_EQ(fs_.read("/machine1/r/ab/out.txt"), "A\nB\n");
  EXPECT_TRUE(fs_.list("/local-cache/ac").empty());
  EXPECT_TRUE(fs_.list("/local-cache/cas").empty());
  log_.clear();
  remote_.calls.clear();
  auto second = build(r, "/machine2");
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second.count(NodeStatus::kCached), 3u);
  EXPECT_EQ(log_.total(), 0);
  EXPECT_EQ(remote_.count("lookup"), 3u);
  EXPECT_EQ(remote_.count("materialize"), 3u);
  EXPECT_EQ(remote_.count("store"), 0u);
  EXPECT_EQ(fs_.read("/machine2/r/ab/out.txt"), "A\nB\n");
}

// Every result is stored only after the blobs it names were made durable, and the results are
// made durable before the build returns.
TEST_F(BuildSeamsTest, BlobsAreMadeDurableBeforeTheResultsNamingThem) {
  ASSERT_TRUE(build(load(kRecipe), "/o").ok());
  const auto& c = remote_.calls;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c[i].rfind("store ", 0) != 0) continue;
    const auto durable = std::find_if(c.begin(), c.begin() + long(i),
                                      [](const std::string& s) { return s.rfind("durable blobs", 0) == 0; });
    EXPECT_NE(durable, c.begin() + long(i)) << c[i] << " came before any blob was made durable";
  }
  ASSERT_FALSE(c.empty());
  EXPECT_EQ(c.back().rfind("durable results", 0), 0u) << c.back();
}

// The runner decides how a node runs: the loop hands it each stale node with its key and its
// inputs' files, and publishes what it stored; dependents see its outputs.
TEST_F(BuildSeamsTest, ARunnerRunsEachStaleNodeWithItsInputs) {
  RecordingRunner runner(fs_, remote_);
  const Recipe r = load(kRecipe);
  auto s = build(r, "/o", &runner);
  ASSERT_TRUE(s.ok());
  EXPECT_EQ(log_.total(), 0);  // no stage ran in this process
  ASSERT_EQ(runner.jobs.size(), 3u);
  EXPECT_EQ(runner.jobs[2], "ab <- 2 input(s), key " + s.nodes[2].key.substr(0, 8));  // after its inputs
  std::sort(runner.jobs.begin(), runner.jobs.begin() + 2);
  EXPECT_EQ(runner.jobs[0], "a <- 0 input(s), key " + s.nodes[0].key.substr(0, 8));
  EXPECT_EQ(runner.jobs[1], "b <- 0 input(s), key " + s.nodes[1].key.substr(0, 8));
  EXPECT_EQ(fs_.read("/o/r/ab/out.txt"), "ab:a:b:");
  // The same recipe again: every result is in the cache, the runner gets nothing.
  runner.jobs.clear();
  EXPECT_EQ(build(r, "/other", &runner).count(NodeStatus::kCached), 3u);
  EXPECT_TRUE(runner.jobs.empty());
}

// A dry run is a runner that runs nothing: no store, no blob, nothing published.
TEST_F(BuildSeamsTest, ADryRunStoresAndPublishesNothing) {
  BuildOptions dry;
  dry.dry_run = true;
  auto s = build(load(kRecipe), "/o", nullptr, dry);
  EXPECT_EQ(s.count(NodeStatus::kWouldBuild), 3u);
  EXPECT_EQ(remote_.count("store"), 0u);
  EXPECT_EQ(remote_.count("put"), 0u);
  EXPECT_FALSE(fs_.stat("/o/r/a"));
  EXPECT_EQ(log_.total(), 0);
}

// A blob the store holds with the wrong bytes is never published: the node runs again and the
// store gets the right bytes.
TEST_F(BuildSeamsTest, ACorruptBlobInTheStoreIsRebuilt) {
  const Recipe r = load(kRecipe);
  auto first = build(r, "/machine1");
  ASSERT_TRUE(first.ok());
  const Digest a = first.nodes[0].outputs.at(0).digest;
  remote_.blobs[a.hash] = "tampered";
  log_.clear();
  auto second = build(r, "/machine2");
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second.nodes[0].status, NodeStatus::kBuilt);
  EXPECT_EQ(log_.count("a"), 1);
  EXPECT_EQ(fs_.read("/machine2/r/a/out.txt"), "A\n");
  EXPECT_EQ(remote_.blobs.at(a.hash), "A\n");
}

}  // namespace
}  // namespace sylva
