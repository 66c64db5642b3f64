// The executor end to end, on the in-memory file system and on real temporary directories:
// caching, incrementality, corruption, failures, determinism, cancellation, concurrency, explain.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "pipeline/cache.h"
#include "pipeline/digest_cache.h"
#include "pipeline/executor.h"
#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/fake_filesystem.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

// Runs on both file systems (TEST_P): the real disk in a temporary directory, and the in-memory
// fake (tests/support/fake_filesystem.h) under "/t". Tests of what only a real disk has (hard
// link counts, permissions, flock between builds, file times) use RealDiskBuildTest.
class BuildTest : public ::testing::TestWithParam<bool> {
 protected:
  BuildTest() : dir_(GetParam() ? fs::path("/t") : tmp_.path()) { test::register_test_stages(reg_, &log_); }

  bool fake() const { return GetParam(); }
  FileSystem& fsys() { return fake() ? static_cast<FileSystem&>(fake_) : real_; }
  void write(const fs::path& p, const std::string& bytes) {
    if (fake())
      fake_.put(p.string(), bytes);
    else
      test::write_file(p, bytes);
  }
  std::string read(const fs::path& p) { return fsys().read(p).value_or("<missing " + p.string() + ">"); }
  bool exists(const fs::path& p) { return fsys().stat(p).has_value(); }
  // CAS blobs are read-only on the real disk.
  void make_writable(const fs::path& p) {
    if (!fake()) fs::permissions(p, fs::perms::owner_write, fs::perm_options::add);
  }

  Recipe load(const std::string& yaml) {
    write(dir_ / "r.yaml", yaml);
    Diagnostics d;
    auto r = load_recipe(dir_ / "r.yaml", reg_, fsys(), d);
    EXPECT_TRUE(r) << d.str();
    return r ? *r : Recipe{};
  }

  BuildSummary build(const Recipe& r, BuildOptions opt = {}, const fs::path& cache_dir = {}) {
    Cache cache(fsys(), cache_dir.empty() ? dir_ / "cache" : cache_dir);
    BuildEnv env{fsys(), cache, dir_ / "out" / r.name, clock_, &cancel_, nullptr};
    std::string err;
    auto s = run_build(r, env, opt, &err);
    EXPECT_EQ(err, "");
    return s;
  }

  std::string out(const std::string& node) { return read(dir_ / "out" / "r" / node / "out.txt"); }
  std::vector<std::string> explain(const Recipe& r, const std::string& node) {
    Cache cache(fsys(), dir_ / "cache");
    BuildEnv env{fsys(), cache, dir_ / "out" / r.name, clock_, nullptr, nullptr};
    return explain_node(r, env, node);
  }
  const NodeReport& report(const BuildSummary& s, const std::string& name) {
    for (const auto& n : s.nodes)
      if (n.name == name) return n;
    throw std::runtime_error("no node " + name);
  }

  test::TempDir tmp_;
  StageRegistry reg_;
  test::RunLog log_;
  RealFileSystem real_;
  test::FakeFileSystem fake_;
  const fs::path dir_;
  SteadyClock clock_;
  std::atomic<bool> cancel_{false};
};

INSTANTIATE_TEST_SUITE_P(OnBothFileSystems, BuildTest, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& i) {
                           return i.param ? "Fake" : "RealDisk";
                         });

class RealDiskBuildTest : public BuildTest {};
INSTANTIATE_TEST_SUITE_P(RealDisk, RealDiskBuildTest, ::testing::Values(false),
                         [](const ::testing::TestParamInfo<bool>&) { return "RealDisk"; });

const char* kChain =
    "version: 1\nname: r\nnodes:\n"
    "  a:\n    stage: text\n    with: { text: A, count: ${N} }\n"
    "  b:\n    stage: text\n    with: { text: B }\n"
    "  ab:\n    stage: concat\n    needs: [a, b]\n"
    "  top:\n    stage: concat\n    needs: ab\n    with: { suffix: '!' }\n";

std::string chain(int n) {
  std::string s = kChain;
  s.replace(s.find("${N}"), 4, std::to_string(n));
  return s;
}

TEST_P(BuildTest, FirstBuildRunsEverythingSecondRunsNothing) {
  Recipe r = load(chain(2));
  auto s1 = build(r);
  EXPECT_TRUE(s1.ok());
  EXPECT_EQ(s1.count(NodeStatus::kBuilt), 4u);
  EXPECT_EQ(out("top"), out("a") + out("b") + "!");
  EXPECT_EQ(out("b"), "B\n");
  log_.clear();
  auto s2 = build(r);
  EXPECT_EQ(s2.count(NodeStatus::kCached), 4u);
  EXPECT_EQ(s2.count(NodeStatus::kBuilt), 0u);
  EXPECT_EQ(log_.total(), 0);
}

// Two nodes whose outputs have the same bytes share one CAS blob, so out/x/out.txt and
// out/y/out.txt are hard links of one inode: publishing y (a link) changes the inode's ctime
// under x's digest record. The engine accounts for its own links, so the second build is a
// no-op that writes nothing, and so is the third (before, every build republished a node and
// rewrote the digest records, the default recipe's no-op took 150 ms instead of 8).
TEST_P(RealDiskBuildTest, NodesSharingABlobMakeANoOpThatWritesNothing) {
  Recipe r = load(
      "version: 1\nname: r\nnodes:\n"
      "  x:\n    stage: text\n    with: { text: same }\n"
      "  y:\n    stage: text\n    with: { text: same }\n"
      "  z:\n    stage: concat\n    needs: [x, y]\n");
  ASSERT_TRUE(build(r).ok());  // y is a cache hit of x's action
  const fs::path records = dir_ / "out" / "r" / ".sylva" / "digests";
  ASSERT_EQ(fs::hard_link_count(dir_ / "out" / "r" / "x" / "out.txt"), 3u);  // CAS, x, y
  std::this_thread::sleep_for(std::chrono::milliseconds(20));                // past the racy rule's tick
  build(r);  // may settle what the first build could not trust yet
  const auto settled = fsys().stat(records);
  ASSERT_TRUE(settled);
  for (int i = 0; i < 2; ++i) {
    auto s = build(r);
    EXPECT_EQ(s.count(NodeStatus::kCached), 3u);
    const auto now = fsys().stat(records);
    ASSERT_TRUE(now);
    EXPECT_EQ(now->mtime_ns, settled->mtime_ns) << "build " << i + 3 << " rewrote the digest records";
    EXPECT_EQ(now->ino, settled->ino) << "build " << i + 3 << " rewrote the digest records";
  }
}

TEST_P(BuildTest, ChangingOneParameterRebuildsOnlyThatNodeAndDependents) {
  auto s1 = build(load(chain(2)));
  ASSERT_TRUE(s1.ok());
  log_.clear();
  Recipe r2 = load(chain(3));
  EXPECT_EQ(explain(r2, "a"),
            (std::vector<std::string>{"'a' will rebuild: parameter 'count' changed: 2 -> 3"}));
  EXPECT_EQ(explain(r2, "top"),
            (std::vector<std::string>{"'top' will rebuild because its input 'ab' will rebuild"}));
  EXPECT_EQ(explain(r2, "b")[0].substr(0, 26), "'b' is up to date (action ");
  auto s2 = build(r2);
  EXPECT_EQ(s2.count(NodeStatus::kBuilt), 3u);
  EXPECT_EQ(report(s2, "b").status, NodeStatus::kCached);
  EXPECT_EQ(log_.count("a"), 1);
  EXPECT_EQ(log_.count("b"), 0);
  EXPECT_EQ(log_.count("ab"), 1);
  EXPECT_EQ(log_.count("top"), 1);
}

TEST_P(BuildTest, SameOutputUpstreamStopsRebuildPropagation) {
  // Changing `mode` on a node whose text is already upper case changes its key but not its
  // bytes: dependents keep their keys (inputs are hashed by content) and stay cached.
  build(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { text: X }\n"
           "  b:\n    stage: concat\n    needs: a\n"));
  log_.clear();
  auto s =
      build(load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { text: X, mode: upper }\n"
                 "  b:\n    stage: concat\n    needs: a\n"));
  EXPECT_EQ(report(s, "a").status, NodeStatus::kBuilt);
  EXPECT_EQ(report(s, "b").status, NodeStatus::kCached);
}

TEST_P(BuildTest, EditedInputFileRebuildsAndExplainSaysWhich) {
  const std::string yaml =
      "version: 1\nname: r\nnodes:\n  f:\n    stage: readfile\n    with: { file: in.txt }\n";
  write(dir_ / "in.txt", "one");
  Recipe r = load(yaml);
  build(r);
  EXPECT_EQ(out("f"), "one");
  write(dir_ / "in.txt", "two");
  // A Recipe carries its files' stats as of loading (Recipe::file_stats); like every `sylva`
  // invocation, load it again after the edit.
  r = load(yaml);
  const auto why = explain(r, "f");
  ASSERT_EQ(why.size(), 1u);
  EXPECT_EQ(why[0].substr(0, why[0].find(" changed")),
            "'f' will rebuild: file '" + (dir_ / "in.txt").string() + "' (parameter 'file')");
  auto s = build(r);
  EXPECT_EQ(s.count(NodeStatus::kBuilt), 1u);
  EXPECT_EQ(out("f"), "two");
}

TEST_P(BuildTest, CorruptBlobIsDetectedAndRebuilt) {
  Recipe r = load(chain(5));
  auto s1 = build(r);
  const Digest d = report(s1, "a").outputs.at(0).digest;
  Cache cache(fsys(), dir_ / "cache");
  const fs::path blob = cache.blob_path(d.hash);
  // Same size, different bytes: only hashing can tell.
  make_writable(blob);
  std::string bytes = read(blob);
  bytes[0] = bytes[0] == 'Z' ? 'Y' : 'Z';
  write(blob, bytes);
  fsys().remove_all(dir_ / "out");  // force the blob to be read
  log_.clear();
  auto s2 = build(r);
  EXPECT_TRUE(s2.ok());
  EXPECT_EQ(report(s2, "a").status, NodeStatus::kBuilt);
  EXPECT_EQ(log_.count("a"), 1);
  EXPECT_EQ(read(blob), out("a"));  // the blob was replaced by the right bytes
  EXPECT_EQ(sha256_hex(out("a")), d.hash);
}

TEST_P(RealDiskBuildTest, TruncatedBlobIsAMissAndEditedOutputIsRepaired) {
  Recipe r = load(chain(1));
  auto s1 = build(r);
  Cache cache(fsys(), dir_ / "cache");
  const fs::path blob = cache.blob_path(report(s1, "b").outputs.at(0).digest.hash);
  // Replace the blob by a truncated file (a new inode: out/r/b/out.txt keeps the old bytes, and
  // its ctime changed with its link count: a real disk's hard links, which the fake does not model).
  fsys().remove(blob);
  write(blob, "");
  // An editor's save: a new file under the output's name, not a write through the hard link.
  fsys().remove(dir_ / "out/r/top/out.txt");
  write(dir_ / "out/r/top/out.txt", "tampered");
  write(dir_ / "out/r/top/stray.txt", "junk");
  log_.clear();
  auto s2 = build(r);
  EXPECT_EQ(report(s2, "b").status, NodeStatus::kBuilt);  // size mismatch: not a hit
  EXPECT_EQ(report(s2, "top").status, NodeStatus::kCached);
  EXPECT_EQ(out("top"), out("a") + "B\n!");
  EXPECT_FALSE(exists(dir_ / "out/r/top/stray.txt"));
}

// Outputs are hard links to their read-only CAS blobs (stored once). A write through the link
// (only root, or after chmod, can make one) changes the blob too: the next build sees the
// changed stat, hashes, finds the blob corrupt, deletes it and rebuilds; nothing corrupt is used.
TEST_P(RealDiskBuildTest, OutputsAreReadOnlyHardLinksAndAWriteThroughOneIsRepaired) {
  Recipe r = load(chain(1));
  auto s1 = build(r);
  Cache cache(fsys(), dir_ / "cache");
  const fs::path blob = cache.blob_path(report(s1, "top").outputs.at(0).digest.hash);
  const fs::path published = dir_ / "out/r/top/out.txt";
  EXPECT_TRUE(fs::equivalent(blob, published));
  EXPECT_EQ(fs::status(published).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const std::string good = out("top");
  fs::permissions(published, fs::perms::owner_write, fs::perm_options::add);
  std::string bad = good;
  bad[0] = bad[0] == 'Z' ? 'Y' : 'Z';
  write(published, bad);  // in place: the blob changes with it
  EXPECT_EQ(read(blob), bad);
  log_.clear();
  auto s2 = build(r);
  EXPECT_TRUE(s2.ok());
  EXPECT_EQ(report(s2, "top").status, NodeStatus::kBuilt);
  EXPECT_EQ(log_.count("top"), 1);
  EXPECT_EQ(out("top"), good);
  EXPECT_EQ(read(blob), good);
}

TEST_P(BuildTest, CacheVerifyAndGc) {
  Recipe r = load(chain(1));
  auto s = build(r);
  Cache cache(fsys(), dir_ / "cache");
  auto st = cache.stats();
  EXPECT_EQ(st.actions, 4u);
  EXPECT_EQ(st.blobs, 4u);
  EXPECT_EQ(cache.verify_all().blobs_removed, 0u);
  const fs::path blob = cache.blob_path(report(s, "a").outputs[0].digest.hash);
  make_writable(blob);
  write(blob, "garbage");
  const VerifyResult v = cache.verify_all();
  EXPECT_EQ(v.blobs_removed, 1u);
  EXPECT_EQ(v.actions_removed, 1u);  // the result that named it goes too
  // An orphan blob is collected; blobs of live results are kept.
  write(cache.blob_path(std::string(64, 'e')), "orphan");
  auto g = cache.gc(0);
  EXPECT_EQ(g.blobs_removed, 1u);
  EXPECT_EQ(cache.stats().blobs, 3u);
}

TEST_P(BuildTest, FailureStopsDependentsAndKeepGoingBuildsTheRest) {
  const char* yaml =
      "version: 1\nname: r\nnodes:\n"
      "  bad:\n    stage: text\n    with: { fail: true }\n"
      "  after:\n    stage: concat\n    needs: bad\n"
      "  good:\n    stage: text\n    with: { sleep_ms: 30 }\n"
      "  good2:\n    stage: concat\n    needs: good\n";
  Recipe r = load(yaml);
  BuildOptions one;
  one.jobs = 1;  // deterministic order: bad runs first, then the build stops
  auto s = build(r, one);
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(report(s, "bad").status, NodeStatus::kFailed);
  EXPECT_EQ(report(s, "bad").error, "asked to fail");
  EXPECT_EQ(report(s, "after").status, NodeStatus::kSkipped);
  EXPECT_EQ(report(s, "after").error, "input 'bad' failed");
  EXPECT_FALSE(exists(dir_ / "out/r/bad"));
  BuildOptions kg;
  kg.keep_going = true;
  auto s2 = build(r, kg, dir_ / "cache2");
  EXPECT_EQ(report(s2, "bad").status, NodeStatus::kFailed);
  EXPECT_EQ(report(s2, "after").status, NodeStatus::kSkipped);
  EXPECT_EQ(report(s2, "good").status, NodeStatus::kBuilt);
  EXPECT_EQ(report(s2, "good2").status, NodeStatus::kBuilt);
}

std::string wide_recipe(int width) {
  std::string y = "version: 1\nname: r\nnodes:\n";
  for (int i = 0; i < width; ++i)
    y += "  n" + std::to_string(i) + ":\n    stage: text\n    with: { text: t" + std::to_string(i) +
         ", count: 20, seed: " + std::to_string(i) + " }\n";
  for (int i = 0; i < width; ++i)
    y += "  c" + std::to_string(i) + ":\n    stage: concat\n    needs: [n" + std::to_string(i) + ", n" +
         std::to_string((i + 1) % width) + "]\n";
  y += "  all:\n    stage: concat\n    needs: 'c*'\n";
  return y;
}

TEST_P(BuildTest, TwoHundredNodeNoOpRebuildRunsNothing) {
  Recipe r = load(wide_recipe(100));
  ASSERT_EQ(r.nodes.size(), 201u);
  auto s1 = build(r);
  EXPECT_EQ(s1.count(NodeStatus::kBuilt), 201u);
  log_.clear();
  auto s2 = build(r);
  EXPECT_EQ(s2.count(NodeStatus::kCached), 201u);
  EXPECT_EQ(log_.total(), 0);
}

TEST_P(BuildTest, OutputsAreIdenticalWhateverTheThreadCount) {
  Recipe r = load(wide_recipe(40));
  BuildOptions j1, j8;
  j1.jobs = 1;
  j8.jobs = 8;
  auto s1 = build(r, j1, dir_ / "cache1");
  const std::string all1 = out("all");
  fsys().remove_all(dir_ / "out");
  auto s8 = build(r, j8, dir_ / "cache8");
  EXPECT_EQ(s8.count(NodeStatus::kBuilt), r.nodes.size());  // fresh cache: really rebuilt
  EXPECT_EQ(out("all"), all1);
  ASSERT_EQ(s1.nodes.size(), s8.nodes.size());
  for (std::size_t i = 0; i < s1.nodes.size(); ++i) {
    EXPECT_EQ(s1.nodes[i].name, s8.nodes[i].name);
    EXPECT_EQ(s1.nodes[i].key, s8.nodes[i].key);
    EXPECT_EQ(s1.nodes[i].outputs.at(0).digest, s8.nodes[i].outputs.at(0).digest);
  }
}

TEST_P(BuildTest, SeedChangesOutputAndIsTheOnlySourceOfRandomness) {
  auto s1 =
      build(load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { count: 8, seed: 1 }\n"));
  const std::string one = out("a");
  build(load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { count: 8, seed: 2 }\n"));
  EXPECT_NE(out("a"), one);
  fsys().remove_all(dir_ / "cache");
  build(load("version: 1\nname: r\nnodes:\n  renamed:\n    stage: text\n    with: { count: 8, seed: 1 }\n"));
  EXPECT_EQ(read(dir_ / "out/r/renamed/out.txt"), one);
}

TEST_P(BuildTest, TargetsBuildOnlyTheirClosure) {
  Recipe r = load(chain(1));
  BuildOptions opt;
  opt.targets = {"ab"};
  auto s = build(r, opt);
  EXPECT_EQ(s.nodes.size(), 3u);
  EXPECT_FALSE(exists(dir_ / "out/r/top"));
  Cache cache(fsys(), dir_ / "cache");
  BuildEnv env{fsys(), cache, dir_ / "out/r", clock_, nullptr, nullptr};
  opt.targets = {"abc"};
  std::string err;
  run_build(r, env, opt, &err);
  EXPECT_EQ(err, "unknown target 'abc'; did you mean 'ab'?");
}

// A node removed from (or renamed in) the recipe takes its published directory and explain
// record with it; what sylva did not publish there stays, and a dry run only names them.
TEST_P(BuildTest, NodesNoLongerInTheRecipeLoseTheirOutputs) {
  ASSERT_TRUE(build(load(chain(1))).ok());
  const fs::path o = dir_ / "out" / "r";
  write(o / "notes.txt", "mine\n");
  write(o / "by_hand" / "keep.txt", "");  // a directory of the user's
  const std::string renamed =
      "version: 1\nname: r\nnodes:\n"
      "  a:\n    stage: text\n    with: { text: A, count: 1 }\n"
      "  b2:\n    stage: text\n    with: { text: B }\n"
      "  ab:\n    stage: concat\n    needs: [a, b2]\n";
  BuildOptions dry;
  dry.dry_run = true;
  auto d = build(load(renamed), dry);
  EXPECT_EQ(d.removed, (std::vector<std::string>{"b", "top"}));
  EXPECT_TRUE(exists(o / "b" / "out.txt"));
  EXPECT_TRUE(exists(o / "top" / "out.txt"));
  auto s = build(load(renamed));
  ASSERT_TRUE(s.ok());
  EXPECT_EQ(s.removed, (std::vector<std::string>{"b", "top"}));
  EXPECT_FALSE(exists(o / "b"));
  EXPECT_FALSE(exists(o / "top"));
  EXPECT_FALSE(exists(o / ".sylva" / "b.json"));
  EXPECT_FALSE(exists(o / ".sylva" / "top.json"));
  EXPECT_TRUE(exists(o / ".sylva" / "a.json"));
  EXPECT_EQ(out("b2"), "B\n");
  EXPECT_EQ(read(o / "notes.txt"), "mine\n");
  EXPECT_TRUE(exists(o / "by_hand"));
  std::vector<std::string> entries;
  for (const auto& e : fsys().list(o)) entries.push_back(e);
  EXPECT_EQ(entries, (std::vector<std::string>{".sylva", "a", "ab", "b2", "by_hand", "notes.txt"}));
  // The records forgot them: the next build removes nothing, and `top` comes back when declared.
  EXPECT_TRUE(build(load(renamed)).removed.empty());
  auto back = build(load(chain(1)));
  EXPECT_EQ(back.removed, (std::vector<std::string>{"b2"}));
  EXPECT_EQ(out("top"), out("a") + "B\n!");
  // Records naming no node directory (a damaged or forged records file) remove nothing.
  {
    DigestCache records(fsys(), o / ".sylva" / "digests");
    records.load();
    const auto a = records.published("a");
    ASSERT_TRUE(a);
    for (const char* name : {"..", ".sylva", "../r", "a/b", ""}) records.set_published(name, *a);
    ASSERT_TRUE(records.save());
  }
  auto forged = build(load(chain(1)));
  EXPECT_TRUE(forged.removed.empty()) << ::testing::PrintToString(forged.removed);
  EXPECT_TRUE(exists(o / ".sylva" / "a.json"));
  EXPECT_TRUE(exists(o / "notes.txt"));
}

TEST_P(BuildTest, DryRunRunsNothingAndPredicts) {
  Recipe r = load(chain(1));
  BuildOptions dry;
  dry.dry_run = true;
  auto s = build(r, dry);
  EXPECT_EQ(s.count(NodeStatus::kWouldBuild), 4u);
  EXPECT_EQ(log_.total(), 0);
  EXPECT_FALSE(exists(dir_ / "out/r/a"));
  build(load(chain(2)));
  auto s2 = build(r, dry);
  EXPECT_EQ(report(s2, "b").status, NodeStatus::kUpToDate);
  EXPECT_EQ(report(s2, "a").status, NodeStatus::kWouldBuild);
  EXPECT_EQ(report(s2, "top").status, NodeStatus::kWouldBuild);
}

TEST_P(BuildTest, CancellationStopsPromptlyAndLeavesNoPartialArtifact) {
  Recipe r = load(
      "version: 1\nname: r\nnodes:\n  slow:\n    stage: text\n    with: { sleep_ms: 20000 }\n"
      "  next:\n    stage: concat\n    needs: slow\n");
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    cancel_ = true;
  });
  const auto t0 = std::chrono::steady_clock::now();
  auto s = build(r);
  stopper.join();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
  EXPECT_EQ(report(s, "slow").status, NodeStatus::kInterrupted);
  EXPECT_EQ(report(s, "next").status, NodeStatus::kInterrupted);
  EXPECT_TRUE(s.interrupted());
  EXPECT_FALSE(exists(dir_ / "out/r/slow"));
  Cache cache(fsys(), dir_ / "cache");
  EXPECT_EQ(cache.stats().actions, 0u);
  EXPECT_EQ(cache.stats().tmp_entries, 0u);  // scratch removed
}

TEST_P(RealDiskBuildTest, ConcurrentBuildsShareOneCacheSafely) {
  Recipe r = load(wide_recipe(30));
  BuildSummary s1, s2;
  // Two independent builds (separate out dirs, one cache), as two processes would run them.
  std::thread t1([&] {
    Cache cache(fsys(), dir_ / "cache");
    BuildEnv env{fsys(), cache, dir_ / "out1/r", clock_, nullptr, nullptr};
    std::string e;
    s1 = run_build(r, env, {}, &e);
  });
  std::thread t2([&] {
    Cache cache(fsys(), dir_ / "cache");
    BuildEnv env{fsys(), cache, dir_ / "out2/r", clock_, nullptr, nullptr};
    std::string e;
    s2 = run_build(r, env, {}, &e);
  });
  t1.join();
  t2.join();
  EXPECT_TRUE(s1.ok());
  EXPECT_TRUE(s2.ok());
  // The per-action lock means each action ran once; the other build found it cached.
  EXPECT_EQ(s1.count(NodeStatus::kBuilt) + s2.count(NodeStatus::kBuilt), r.nodes.size());
  EXPECT_EQ(log_.total(), static_cast<int>(r.nodes.size()));
  EXPECT_EQ(read(dir_ / "out1/r/all/out.txt"), read(dir_ / "out2/r/all/out.txt"));
}

}  // namespace
}  // namespace sylva

namespace sylva {
namespace {

// After a build that stored blobs, least recently used results are evicted while the cache is
// above its limit; this build's own results (just used) stay.
TEST_P(RealDiskBuildTest, CacheAboveItsLimitEvictsLeastRecentlyUsedResultsAfterABuild) {
  build(load("version: 1\nname: r\nnodes:\n  old:\n    stage: text\n    with: { text: OLD, count: 200 }\n"));
  Cache cache(fsys(), dir_ / "cache");
  fs::last_write_time(cache.action_path(build(load("version: 1\nname: r\nnodes:\n  old:\n    stage: text\n   "
                                                   " with: { text: OLD, count: 200 }\n"))
                                            .nodes[0]
                                            .key),
                      fs::file_time_type::clock::now() - std::chrono::hours(48));
  const std::uint64_t old_bytes = cache.blob_bytes();
  BuildOptions opt;
  opt.cache_max_bytes = old_bytes;  // room for one of the two results
  auto s = build(
      load("version: 1\nname: r\nnodes:\n  new:\n    stage: text\n    with: { text: NEW, count: 200 }\n"),
      opt);
  EXPECT_EQ(s.evicted.actions_removed, 1u);
  EXPECT_EQ(s.evicted.blobs_removed, 1u);
  EXPECT_EQ(cache.stats().actions, 1u);
  EXPECT_TRUE(cache.lookup(s.nodes[0].key));
  EXPECT_LE(cache.blob_bytes(), old_bytes);
}

// gc and builds exclude each other through one lock: builds share it, gc needs it alone.
TEST_P(RealDiskBuildTest, GcWaitsForRunningBuilds) {
  Cache cache(fsys(), dir_ / "cache");
  {
    auto building = cache.lock_for_build();
    auto other_build = Cache(fsys(), dir_ / "cache").lock_for_build();  // builds run side by side
    ASSERT_TRUE(building && other_build);
    EXPECT_FALSE(cache.try_lock_for_gc());
  }
  EXPECT_TRUE(cache.try_lock_for_gc());
}

}  // namespace
}  // namespace sylva
