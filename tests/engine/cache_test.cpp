// The cache over an in-memory file system: what is written where, and what happens when a
// write fails or a stored result is damaged.
#include "pipeline/cache.h"

#include <gtest/gtest.h>

#include "tests/support/fake_filesystem.h"

namespace sylva {
namespace {

const std::string kKey(64, 'a');

TEST(CacheTest, PutFileMovesTheFileIntoTheCasUnderItsDigest) {
  test::FakeFileSystem fs;
  fs.put("/s/out.txt", "hello");
  Cache cache(fs, "/c");
  std::int64_t known_at = 0;
  auto d = cache.put_file("/s/out.txt", &known_at);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->hash, sha256_hex("hello"));
  EXPECT_EQ(d->size, 5u);
  const std::string blob = "/c/cas/" + d->hash.substr(0, 2) + "/" + d->hash;
  EXPECT_EQ(fs.files.at(blob), "hello");
  EXPECT_FALSE(fs.files.count("/s/out.txt"));  // moved, not copied
  EXPECT_EQ(fs.writes, std::vector<std::string>{blob});
  // Its mtime sits just below the clock read before hashing: any later write is newer.
  EXPECT_EQ(known_at, fs.now);
  EXPECT_EQ(fs.stat(blob)->mtime_ns, fs.now - 1);
}

TEST(CacheTest, HitRequiresEveryBlobPresentWithItsSize) {
  test::FakeFileSystem fs;
  fs.put("/s/a", "aaa");
  Cache cache(fs, "/c");
  auto d = *cache.put_file("/s/a");
  cache.store(kKey, ActionResult{{{"a", d}}});
  ASSERT_TRUE(cache.lookup(kKey));
  EXPECT_EQ(cache.lookup(kKey)->outputs.at(0).digest, d);
  fs.files[cache.blob_path(d.hash).string()] = "aaaa";  // wrong size
  EXPECT_FALSE(cache.lookup(kKey));
  fs.files.erase(cache.blob_path(d.hash).string());  // missing
  EXPECT_FALSE(cache.lookup(kKey));
}

TEST(CacheTest, DamagedActionResultIsAMissNotAnError) {
  test::FakeFileSystem fs;
  Cache cache(fs, "/c");
  fs.files[cache.action_path(kKey).string()] = "{not json";
  EXPECT_FALSE(cache.lookup(kKey));
  fs.files[cache.action_path(kKey).string()] = R"({"outputs":[{"name":"x","hash":"../../etc","size":1}]})";
  EXPECT_FALSE(cache.lookup(kKey));  // a hash that is not 64 hex digits is rejected
}

TEST(CacheTest, MaterializeRefusesAndDeletesCorruptBlob) {
  test::FakeFileSystem fs;
  fs.put("/s/a", "good");
  Cache cache(fs, "/c");
  auto d = *cache.put_file("/s/a");
  fs.files[cache.blob_path(d.hash).string()] = "bad!";  // same size, other bytes
  EXPECT_FALSE(cache.materialize(d, "/out/a"));
  EXPECT_FALSE(fs.files.count("/out/a"));
  EXPECT_FALSE(fs.files.count(cache.blob_path(d.hash).string()));
}

TEST(CacheTest, FailedBlobWriteStoresNothing) {
  test::FakeFileSystem fs;
  fs.put("/s/a", "data");
  fs.fail_writes_containing = "/cas/";
  Cache cache(fs, "/c");
  EXPECT_FALSE(cache.put_file("/s/a"));
  EXPECT_TRUE(fs.writes.empty());
}

TEST(CacheTest, GcEvictsLeastRecentlyUsedAboveBudget) {
  test::FakeFileSystem fs;
  Cache cache(fs, "/c");
  const std::string k1(64, '1'), k2(64, '2');
  fs.put("/s/old", std::string(100, 'o'));
  fs.put("/s/new", std::string(100, 'n'));
  cache.store(k1, ActionResult{{{"o", *cache.put_file("/s/old")}}});
  cache.store(k2, ActionResult{{{"n", *cache.put_file("/s/new")}}});
  fs.ages[cache.action_path(k1).string()] = 500;  // k1 used long ago
  fs.ages["/c/tmp/stale"] = 7200;
  fs.files["/c/tmp/stale"] = "x";
  auto r = cache.gc(150);
  EXPECT_EQ(r.actions_removed, 1u);
  EXPECT_EQ(r.blobs_removed, 1u);
  EXPECT_EQ(r.bytes_freed, 100u);
  EXPECT_EQ(r.tmp_removed, 1u);
  EXPECT_TRUE(cache.lookup(k2));
  EXPECT_FALSE(cache.lookup(k1));
}

}  // namespace
}  // namespace sylva
