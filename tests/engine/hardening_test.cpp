// Issue 15's engine items, each as the attack or accident that used to succeed: deadlock of
// same-key nodes with nested parallel loops (4), exceptions that are not std::exception and
// throwing observers (5), crafted action-cache entries (9), per-file publishing under
// concurrent builds and stale outputs after a failure (11), bookkeeping writes that fail
// silently and hashing that ignores Ctrl-C (12), results written before their blobs are
// durable (14).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <future>
#include <thread>

#include "pipeline/cache.h"
#include "pipeline/executor.h"
#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/fake_filesystem.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

class HardeningTest : public ::testing::Test {
 protected:
  HardeningTest() { test::register_test_stages(reg_, &log_); }

  Recipe load(const std::string& yaml, FileSystem& fsys) {
    test::write_file(dir_ / "r.yaml", yaml);
    if (&fsys != &fs_) static_cast<test::FakeFileSystem&>(fsys).put((dir_ / "r.yaml").string(), yaml);
    Diagnostics d;
    auto r = load_recipe(dir_ / "r.yaml", reg_, fsys, d);
    EXPECT_TRUE(r) << d.str();
    return r ? *r : Recipe{};
  }
  Recipe load(const std::string& yaml) { return load(yaml, fs_); }

  BuildSummary build(const Recipe& r, FileSystem& fsys, const fs::path& out, const fs::path& cache_dir,
                     BuildOptions opt = {}, BuildObserver* observer = nullptr) {
    Cache cache(fsys, cache_dir);
    BuildEnv env{fsys, cache, out / r.name, clock_, nullptr, observer};
    std::string err;
    auto s = run_build(r, env, opt, &err);
    EXPECT_EQ(err, "");
    return s;
  }
  BuildSummary build(const Recipe& r, BuildOptions opt = {}, BuildObserver* observer = nullptr) {
    return build(r, fs_, dir_ / "out", dir_ / "cache", opt, observer);
  }

  test::TempDir dir_;
  StageRegistry reg_;
  test::RunLog log_;
  RealFileSystem fs_;
  SteadyClock clock_;
};

// Item 4. Three groups of ten nodes share an action key per group; each runs a parallel loop.
// Without isolation a thread waiting in node A's loop (A holds its key's lock) could pick up
// node B's task, which waits for that lock forever. Run many times; a hang is reported by a
// watchdog (ctest runs each test in its own process, so exiting is safe).
TEST_F(HardeningTest, SameKeyNodesWithNestedParallelLoopsNeverDeadlock) {
  std::string yaml = "version: 1\nname: r\nnodes:\n";
  for (int i = 0; i < 30; ++i)
    yaml += "  n" + std::to_string(i) + ":\n    stage: nested\n    with: { text: k" + std::to_string(i % 3) +
            ", items: 100, micros: 100 }\n";
  Recipe r = load(yaml);
  auto runs = std::async(std::launch::async, [&] {
    for (int round = 0; round < 15; ++round) {
      BuildOptions opt;
      opt.jobs = 4;
      const fs::path d = dir_ / ("round" + std::to_string(round));
      auto s = build(r, fs_, d / "out", d / "cache", opt);
      if (!s.ok()) return round;
    }
    return -1;
  });
  if (runs.wait_for(std::chrono::seconds(120)) != std::future_status::ready) {
    std::fprintf(stderr, "deadlock: same-key nodes with nested parallel loops did not finish in 120 s\n");
    std::_Exit(1);
  }
  EXPECT_EQ(runs.get(), -1);
  EXPECT_EQ(log_.total(), 3 * 15);  // one run per key and build: the others found it in the cache
}

class ThrowingObserver final : public BuildObserver {
 public:
  std::string throw_on;  // "start" or "finish"
  void on_start(const std::string&) override {
    if (throw_on == "start") throw 7;
  }
  void on_finish(const NodeReport& r) override {
    if (throw_on == "finish" && r.name == "ok") throw std::runtime_error("observer bug");
  }
};

// Item 5. Not a std::exception, from a stage or from the observer: the node fails with a
// message, the build goes on, the process does not terminate.
TEST_F(HardeningTest, ExceptionsOfAnyTypeFailTheNodeNeverTheProcess) {
  Recipe r = load(
      "version: 1\nname: r\nnodes:\n"
      "  int:\n    stage: throwing\n    with: { what: int }\n"
      "  logic:\n    stage: throwing\n    with: { what: logic }\n"
      "  ok:\n    stage: throwing\n    with: { what: none }\n");
  BuildOptions keep;
  keep.keep_going = true;
  auto s = build(r, keep);
  ASSERT_EQ(s.nodes.size(), 3u);
  EXPECT_EQ(s.nodes[0].status, NodeStatus::kFailed);
  EXPECT_EQ(s.nodes[0].error,
            "internal error in stage 'throwing': an exception that is not a std::exception");
  EXPECT_EQ(s.nodes[1].error, "internal error in stage 'throwing': a bug");
  EXPECT_EQ(s.nodes[2].status, NodeStatus::kBuilt);

  ThrowingObserver obs;
  obs.throw_on = "finish";
  const fs::path d = dir_ / "second";
  auto s2 = build(r, fs_, d / "out", d / "cache", keep, &obs);
  EXPECT_EQ(s2.nodes[2].status, NodeStatus::kFailed);
  EXPECT_EQ(s2.nodes[2].error, "the build observer failed: observer bug");
  obs.throw_on = "start";
  const fs::path d3 = dir_ / "third";
  auto s3 = build(r, fs_, d3 / "out", d3 / "cache", keep, &obs);
  EXPECT_EQ(s3.nodes[2].status, NodeStatus::kFailed);
  EXPECT_EQ(s3.nodes[2].error, "the build observer failed: an exception that is not a std::exception");
}

// Item 9. Entries in cache/ac are data anyone with write access to a shared cache can forge:
// an output name with a path, an empty output list, another action's entry, an output its
// stage does not declare, an entry without its key. None is used (the node runs), nothing is
// written outside out/, and `cache verify` deletes those it can judge without the stages.
TEST_F(HardeningTest, CraftedActionCacheEntriesAreNeverTrusted) {
  Recipe r = load(
      "version: 1\nname: r\nnodes:\n  a:\n    stage: nested\n    with: { text: x, items: 1 }\n"
      "  b:\n    stage: nested\n    with: { text: y, items: 1 }\n");
  auto s1 = build(r);
  ASSERT_TRUE(s1.ok());
  const std::string key = s1.nodes[0].key, other = s1.nodes[1].key;
  const Digest blob = s1.nodes[0].outputs.at(0).digest;
  Cache cache(fs_, dir_ / "cache");
  auto forge = [&](const std::string& json) {
    const fs::path p = cache.action_path(key);
    fs::permissions(p.parent_path(), fs::perms::owner_all, fs::perm_options::add);
    test::write_file(p, json);
  };
  const std::string entry =
      "{\"name\":\"NAME\",\"hash\":\"" + blob.hash + "\",\"size\":" + std::to_string(blob.size) + "}";
  auto with_name = [&](const std::string& name) {
    std::string e = entry;
    e.replace(e.find("NAME"), 4, name);
    return e;
  };
  const std::vector<std::string> forged = {
      "{\"key\":\"" + key + "\",\"outputs\":[" + with_name("../../../PWNED.txt") + "]}",
      "{\"key\":\"" + key + "\",\"outputs\":[]}",
      "{\"key\":\"" + other + "\",\"outputs\":[" + with_name("out.txt") + "]}",
      "{\"key\":\"" + key + "\",\"outputs\":[" + with_name("other.txt") + "]}",
      "{\"outputs\":[" + with_name("out.txt") + "]}",
  };
  for (std::size_t i = 0; i < forged.size(); ++i) {
    forge(forged[i]);
    log_.clear();
    const fs::path fresh = dir_ / ("fresh" + std::to_string(i));
    auto s = build(r, fs_, fresh / "out", dir_ / "cache");
    EXPECT_TRUE(s.ok()) << i;
    EXPECT_EQ(log_.count("a"), 1) << "forged entry " << i << " was used";
    EXPECT_FALSE(fs::exists(fresh / "PWNED.txt"));
    EXPECT_FALSE(fs::exists(dir_ / "PWNED.txt"));
    EXPECT_EQ(test::read_file(fresh / "out/r/a/out.txt"), "x 0\n");
    forge(forged[i]);
    // An output name its stage does not declare is caught at lookup (the cache alone does not
    // know stages); every other forgery is deleted by `cache verify` too.
    EXPECT_EQ(cache.verify_all().actions_removed, i == 3 ? 0u : 1u) << i;
  }
}

// Item 11. Two builds into one out dir (separate caches, so both run and publish every node)
// used to delete each other's temporary files; publishing is now one directory swap per node.
TEST_F(HardeningTest, ConcurrentBuildsIntoOneOutDirBothSucceed) {
  std::string yaml = "version: 1\nname: r\nnodes:\n";
  for (int i = 0; i < 20; ++i)
    yaml +=
        "  t" + std::to_string(i) + ":\n    stage: text\n    with: { text: T" + std::to_string(i) + " }\n";
  Recipe r = load(yaml);
  for (int round = 0; round < 6; ++round) {
    const fs::path d = dir_ / ("c" + std::to_string(round));
    auto other = std::async(std::launch::async, [&] { return build(r, fs_, dir_ / "out", d / "cache2"); });
    auto mine = build(r, fs_, dir_ / "out", d / "cache1");
    auto theirs = other.get();
    ASSERT_TRUE(mine.ok()) << round << ": " << (mine.errors.empty() ? "" : mine.errors[0]);
    ASSERT_TRUE(theirs.ok()) << round;
    fs::remove(dir_ / "out/r/.sylva/digests");  // the next round publishes everything again
  }
  for (int i = 0; i < 20; ++i) {
    const fs::path node = dir_ / "out/r" / ("t" + std::to_string(i));
    EXPECT_EQ(test::read_file(node / "out.txt"), "T" + std::to_string(i) + "\n");
    EXPECT_EQ(std::distance(fs::directory_iterator(node), fs::directory_iterator()), 1);
  }
  for (const auto& e : fs::directory_iterator(dir_ / "out/r"))  // no staged or displaced directory left
    EXPECT_TRUE(e.path().filename().string()[0] != '.' || e.path().filename() == ".sylva") << e.path();
}

// Item 11. A node whose rebuild fails does not keep its previous outputs under its name.
TEST_F(HardeningTest, AFailedRebuildLeavesNoStaleOutputs) {
  Recipe good = load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { text: old }\n");
  ASSERT_TRUE(build(good).ok());
  ASSERT_EQ(test::read_file(dir_ / "out/r/a/out.txt"), "old\n");
  Recipe bad =
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { text: new, fail: true }\n");
  auto s = build(bad);
  EXPECT_EQ(s.nodes[0].status, NodeStatus::kFailed);
  EXPECT_FALSE(fs::exists(dir_ / "out/r/a"));
  ASSERT_TRUE(build(good).ok());  // and the old result is a cache hit again
  EXPECT_EQ(test::read_file(dir_ / "out/r/a/out.txt"), "old\n");
}

// Item 12. An action result, explain record or digest record that cannot be written fails the
// build (exit 1) with the reason; it used to be ignored (exit 0).
TEST_F(HardeningTest, BookkeepingWritesThatFailFailTheBuildWithTheReason) {
  for (const std::string where : {"/ac/", "<sync>", "/.sylva/a.json", "/.sylva/digests"}) {
    test::FakeFileSystem fake;
    Recipe r = load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { text: A }\n", fake);
    fake.fail_writes_containing = where;
    auto s = build(r, fake, "/o", "/c");
    EXPECT_EQ(s.nodes.at(0).status, NodeStatus::kBuilt) << where;
    EXPECT_FALSE(s.ok()) << where;
    ASSERT_FALSE(s.errors.empty()) << where;
    EXPECT_NE(s.errors[0].find("No space left on device"), std::string::npos) << s.errors[0];
  }
}

// Item 12. Hashing stops at the next 256 KiB when Ctrl-C (or SIGTERM) raised the flag.
TEST_F(HardeningTest, HashingStopsWhenCancelled) {
  const fs::path big = dir_ / "big";
  test::write_file(big, std::string(8 << 20, 'x'));
  RealFileSystem fsys;
  std::atomic<bool> cancel{false};
  fsys.set_cancel_flag(&cancel);
  EXPECT_TRUE(fsys.digest(big));
  cancel = true;
  std::string why;
  EXPECT_FALSE(fsys.digest(big, &why));
  EXPECT_EQ(why, "interrupted");
}

// Item 12 / 2. A FIFO where a file is expected is refused at once, not read forever.
TEST_F(HardeningTest, ReadingAFifoDoesNotBlock) {
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  std::string why;
  EXPECT_FALSE(fs_.read(fifo, &why));
  EXPECT_EQ(why, "not a regular file");
  EXPECT_FALSE(fs_.digest(fifo, &why));
  EXPECT_EQ(why, "not a regular file");
  EXPECT_TRUE(fs_.stat(fifo)->is_other);
}

// Makes `fake` record in `results` every action result written under /c/ac/, checking as each
// is written that every blob it names (under /c/cas/) is already durable.
void record_results_checking_their_blobs(test::FakeFileSystem& fake, std::vector<std::string>& results) {
  fake.on_write = [&fake, &results](const std::string& path) {
    if (path.find("/c/ac/") == std::string::npos) return;
    results.push_back(path);
    auto result = ActionResult::from_json(fake.files.at(path), fs::path(path).filename().string());
    ASSERT_TRUE(result) << path;
    for (const auto& o : result->outputs) {
      const std::string blob = "/c/cas/" + o.digest.hash.substr(0, 2) + "/" + o.digest.hash;
      EXPECT_TRUE(fake.durable(blob)) << path << " was written before blob " << blob << " was durable";
    }
  };
}

// Item 14. No action result is written before the blobs it names are durable (each blob and its
// directory synced since it was moved into place: it survives a power loss), and the results
// themselves are durable before the build returns. Only this build's files are synced.
TEST_F(HardeningTest, ResultsAreWrittenOnlyAfterTheirBlobsAreDurable) {
  test::FakeFileSystem fake;
  Recipe r = load(
      "version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { text: A }\n"
      "  b:\n    stage: text\n    with: { text: B }\n",
      fake);
  std::vector<std::string> results;
  record_results_checking_their_blobs(fake, results);
  ASSERT_TRUE(build(r, fake, "/o", "/c").ok());
  ASSERT_EQ(results.size(), 2u);
  for (const auto& path : results)
    EXPECT_TRUE(fake.durable(path)) << path << " is not durable after the build";
  for (const auto& e : fake.events) {
    if (e.rfind("sync ", 0) == 0) {
      EXPECT_EQ(e.rfind("sync /c", 0), 0u) << "synced what this build did not write: " << e;
    }
  }
  EXPECT_EQ(std::count(fake.events.begin(), fake.events.end(), "syncfs"), 0)
      << "a two-node build waited for syncfs";
}

// Item 14, at scale: a build whose batches hold more than kSyncEachMaxFiles files makes them
// durable with syncfs instead of an fsync per file, and keeps the same guarantee.
TEST_F(HardeningTest, LargeBatchesAreMadeDurableWithOneSyncPerBatch) {
  test::FakeFileSystem fake;
  std::string yaml = "version: 1\nname: r\nnodes:\n";
  for (int i = 0; i < 40; ++i)
    yaml +=
        "  n" + std::to_string(i) + ":\n    stage: text\n    with: { text: T" + std::to_string(i) + " }\n";
  Recipe r = load(yaml, fake);
  std::vector<std::string> results;
  record_results_checking_their_blobs(fake, results);
  BuildOptions one_at_a_time;
  one_at_a_time.jobs = 1;
  ASSERT_TRUE(build(r, fake, "/o", "/c", one_at_a_time).ok());
  ASSERT_EQ(results.size(), 40u);
  for (const auto& path : results)
    EXPECT_TRUE(fake.durable(path)) << path << " is not durable after the build";
  // The results are made durable together at the end: 40 files, one syncfs.
  EXPECT_GE(std::count(fake.events.begin(), fake.events.end(), "syncfs"), 1);
}

}  // namespace
}  // namespace sylva
