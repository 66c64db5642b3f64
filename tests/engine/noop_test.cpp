// No-op builds decide everything from stats (pipeline/digest_cache.h), on the in-memory file
// system, which records every content read: a no-op reads no output, no blob and no unchanged
// input, and writes nothing; the racy-git rule keeps a same-tick edit from hiding.
#include <gtest/gtest.h>

#include <algorithm>

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
constexpr std::int64_t kMs = 1000000;

class NoOpTest : public ::testing::Test {
 protected:
  NoOpTest() { test::register_test_stages(reg_, &log_); }

  // The readfile stage reads its file through its context, i.e. through the fake too.
  void put_input(const std::string& bytes) { fs_.put(input_.string(), bytes); }

  Recipe load() {
    fs_.put("/p/r.yaml",
            "version: 1\nname: r\nnodes:\n"
            "  a:\n    stage: text\n    with: { text: A, count: 3 }\n"
            "  b:\n    stage: text\n    with: { text: B }\n"
            "  f:\n    stage: readfile\n    with: { file: " +
                input_.string() + " }\n");
    Diagnostics d;
    LoadOptions trusted;  // the input lives outside the project root /p
    trusted.confine = false;
    auto r = load_recipe("/p/r.yaml", reg_, fs_, d, trusted);
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

  fs::path input_ = "/data/in.txt";
  StageRegistry reg_;
  test::RunLog log_;
  test::FakeFileSystem fs_;
  SteadyClock clock_;
};

TEST_F(NoOpTest, NoOpBuildReadsNoOutputNoBlobNoInputAndWritesNothing) {
  put_input("input bytes");
  fs_.now += kMs;  // the input is older than the build's clock: settled
  Recipe r = load();
  auto s1 = build(r);
  ASSERT_EQ(s1.count(NodeStatus::kBuilt), 3u);
  ASSERT_TRUE(fs_.files.count("/o/r/f/out.txt"));
  EXPECT_EQ(fs_.files.at("/o/r/f/out.txt"), "input bytes");

  fs_.reads.clear();
  fs_.writes.clear();
  log_.clear();
  auto s2 = build(r);
  EXPECT_EQ(s2.count(NodeStatus::kCached), 3u);
  EXPECT_EQ(log_.total(), 0);
  // What a no-op reads: its digest records. Not an output, not a blob, not the unchanged
  // input, not even the action cache (the records say what this out dir holds).
  EXPECT_EQ(fs_.reads, std::vector<std::string>{"/o/r/.sylva/digests"});
  EXPECT_TRUE(fs_.writes.empty()) << ::testing::PrintToString(fs_.writes);
}

// An input edited within the same clock tick as the build that hashed it, keeping its size,
// has the same size and the same mtime as before: only the racy rule (its mtime was not older
// than the clock when it was hashed, so it was never trusted) makes the next build look again.
TEST_F(NoOpTest, SameTickEditOfAnInputIsNotMissed) {
  put_input("one");
  Recipe r = load();
  build(r);  // same tick as the write
  EXPECT_EQ(fs_.files.at("/o/r/f/out.txt"), "one");
  put_input("two");  // same size, same tick: an identical stat, but for the inode
  fs_.set_mtime(input_, fs_.stat(input_)->mtime_ns);
  auto s2 = build(r);
  EXPECT_EQ(s2.nodes.back().status, NodeStatus::kBuilt);
  EXPECT_EQ(fs_.files.at("/o/r/f/out.txt"), "two");
}

// An output edited in out/ keeping its size is noticed by its stat, hashed, and replaced from
// the CAS: the edit does not survive a build.
TEST_F(NoOpTest, EditedOutputIsNoticedByStatAndRepublished) {
  put_input("input bytes");
  fs_.now += kMs;
  Recipe r = load();
  build(r);
  const std::string good = fs_.files.at("/o/r/a/out.txt");
  fs_.now += kMs;
  fs_.put("/o/r/a/out.txt", std::string(good.size(), 'x'));
  auto s2 = build(r);
  EXPECT_EQ(s2.count(NodeStatus::kCached), 3u);
  EXPECT_EQ(fs_.files.at("/o/r/a/out.txt"), good);
}

// The racy rule itself: a timestamp must be strictly older than the clock read before the
// content was known; whole-second timestamps need two seconds.
TEST(DigestCacheTest, SettledOnlyWhenStrictlyOlderThanTheClock) {
  constexpr std::int64_t kS = 1000000000;
  EXPECT_TRUE(DigestCache::settled(100 * kS + 5, 100 * kS + 6));
  EXPECT_FALSE(DigestCache::settled(100 * kS + 6, 100 * kS + 6));
  EXPECT_FALSE(DigestCache::settled(100 * kS, 101 * kS + 999));
  EXPECT_TRUE(DigestCache::settled(100 * kS, 102 * kS));
}

// Records survive a save and a load; a damaged file is an empty cache, not an error.
TEST(DigestCacheTest, RecordsRoundTripAndDamageIsForgotten) {
  test::FakeFileSystem fs;
  fs.put("/d/x", "xyz");
  fs.now += kMs;
  DigestCache c(fs, "/o/.sylva/digests");
  auto d = c.digest("/d/x");
  ASSERT_TRUE(d);
  const PublishedNode node{
      std::string(64, 'b') + " /c", {{"out.txt", *d}}, *fs.stat("/d/x"), std::string(64, 'c')};
  c.set_published("n", node);
  ASSERT_TRUE(c.save());
  DigestCache c2(fs, "/o/.sylva/digests");
  c2.load();
  fs.reads.clear();
  EXPECT_EQ(c2.digest("/d/x"), d);
  EXPECT_TRUE(fs.reads.empty());
  EXPECT_EQ(c2.published("n"), node);
  fs.files["/o/.sylva/digests"].resize(20);
  DigestCache c3(fs, "/o/.sylva/digests");
  c3.load();
  EXPECT_FALSE(c3.published("n"));
  EXPECT_EQ(c3.digest("/d/x"), d);  // hashed again
}

// Loaded records are looked up in the file's own bytes and written back as they were; changed
// ones shadow them. Whatever mix of loaded and changed records, the saved bytes are those of a
// cache that recorded the same state from scratch (sorted, deterministic), and an unsorted or
// duplicated file (not one sylva wrote) is an empty cache.
TEST(DigestCacheTest, ChangesOverLoadedRecordsSaveTheSameBytesAsAFreshCache) {
  test::FakeFileSystem fs;
  for (const char* f : {"/d/a", "/d/b", "/d/c", "/d/e"}) fs.put(f, std::string("bytes of ") + f);
  fs.now += kMs;
  auto node = [&](char k, const Digest& d) {
    return PublishedNode{std::string(64, k) + " /c", {{"out.txt", d}}, *fs.stat("/d/a"), std::string(64, k)};
  };
  DigestCache first(fs, "/o/digests");
  for (const char* f : {"/d/a", "/d/b", "/d/c"}) ASSERT_TRUE(first.digest(f));
  const Digest da = *first.digest("/d/a");
  first.set_published("n1", node('1', da));
  first.set_published("n2", node('2', da));
  first.set_published("n3", node('3', da));
  ASSERT_TRUE(first.save());

  // Load, then: forget b, record e, re-record a (unchanged: stays clean), replace n2, drop n3.
  DigestCache second(fs, "/o/digests");
  second.load();
  fs.reads.clear();
  EXPECT_EQ(second.digest("/d/a"), da);
  EXPECT_TRUE(fs.reads.empty());
  EXPECT_TRUE(second.holds("/d/a", da));
  EXPECT_FALSE(second.holds("/d/a", Digest{std::string(64, 'f'), da.size}));
  EXPECT_FALSE(second.holds("/d/b", da));
  EXPECT_EQ(second.published("n1"), node('1', da));
  second.forget("/d/b");
  ASSERT_TRUE(second.digest("/d/e"));
  second.set_published("n2", node('9', da));
  second.forget_published("n3");
  EXPECT_FALSE(second.published("n3"));
  EXPECT_EQ(second.published("n2"), node('9', da));
  ASSERT_TRUE(second.save());
  const std::string merged = fs.files.at("/o/digests");

  DigestCache fresh(fs, "/o/fresh");
  for (const char* f : {"/d/e", "/d/c", "/d/a"}) ASSERT_TRUE(fresh.digest(f));
  fresh.set_published("n2", node('9', da));
  fresh.set_published("n1", node('1', da));
  ASSERT_TRUE(fresh.save());
  EXPECT_EQ(fs.files.at("/o/fresh"), merged);

  DigestCache third(fs, "/o/digests");
  third.load();
  fs.reads.clear();
  for (const char* f : {"/d/a", "/d/c", "/d/e"}) EXPECT_TRUE(third.digest(f));
  EXPECT_TRUE(fs.reads.empty());
  EXPECT_TRUE(third.digest("/d/b"));
  EXPECT_EQ(fs.reads, std::vector<std::string>{"/d/b"});  // forgotten: hashed again
  EXPECT_FALSE(third.published("n3"));

  // The same two records in the wrong order: not a file sylva wrote, so nothing is trusted.
  DigestCache two(fs, "/o/two");
  ASSERT_TRUE(two.digest("/d/a"));
  ASSERT_TRUE(two.digest("/d/c"));
  ASSERT_TRUE(two.save());
  std::string bytes = fs.files.at("/o/two");
  const std::size_t a = bytes.find("/d/a") - 1, c = bytes.find("/d/c") - 1;
  ASSERT_LT(a, c);
  const std::string rec_a = bytes.substr(a, c - a), rec_c = bytes.substr(c, bytes.size() - 1 - c);
  bytes.replace(a, rec_a.size() + rec_c.size(), rec_c + rec_a);
  fs.files["/o/two"] = bytes;
  DigestCache swapped(fs, "/o/two");
  swapped.load();
  fs.reads.clear();
  EXPECT_TRUE(swapped.digest("/d/a"));
  EXPECT_EQ(fs.reads, std::vector<std::string>{"/d/a"});
}

}  // namespace
}  // namespace sylva
