// The content-addressed cache (Bazel's vocabulary), shared safely by concurrent builds:
//   <root>/cas/ab/<hash>     output blobs, named by their SHA-256, read-only
//   <root>/ac/ab/<key>       action results: JSON manifest of output name -> digest, naming
//                            its own key
//   <root>/locks/ab/<key>    flock files: one process runs an action at a time
//   <root>/tmp/              temporary files and stage scratch directories
// Every write is temp + rename; a blob is made durable (fsync of the file and of its
// directories, DurableBatch) before an action result names it. An action-cache hit counts only if the entry
// names its own key, lists at least one output, every output name is a valid file name ([A-Za-z0-9_.-], no
// "." or "..": an entry can never name a path outside the node's directory) matching the stage's declared
// output patterns, and every blob it names is present with the recorded size; a blob whose
// content does not hash to its name is deleted when it is read and the action rebuilt, never
// used. Anything else is a miss (and `cache verify` deletes it): a crafted or damaged entry is
// never trusted.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "pipeline/action_cache.h"
#include "pipeline/blob_store.h"
#include "pipeline/digest.h"
#include "pipeline/filesystem.h"

namespace sylva {

// True if output `name` matches one of `patterns` (fnmatch); an empty list accepts any name.
bool output_name_declared(const std::string& name, const std::vector<std::string>& patterns);

struct CacheStats {
  std::uint64_t blobs = 0, blob_bytes = 0, actions = 0, tmp_entries = 0;
};

struct GcResult {
  std::uint64_t actions_removed = 0, blobs_removed = 0, bytes_freed = 0, tmp_removed = 0;
};

struct VerifyResult {
  std::uint64_t blobs_removed = 0, actions_removed = 0;
};

// An action result is a few hundred bytes; anything much larger is not one (never read whole).
inline constexpr std::uint64_t kMaxActionBytes = 1 << 20;

// make_durable() of more files than this calls syncfs(2) once instead of an fsync per file and
// per directory. A one-node build then costs a few fsyncs of its own files, not a wait for every
// other process's dirty pages; a cold build of thousands of nodes (whose batches grow while the
// previous batch is synced) costs one syncfs per batch instead of ~4 fsyncs per node, which on
// ext4 is a journal commit each (docs/performance.md, "Engine").
inline constexpr std::size_t kSyncEachMaxFiles = 16;

// The local cache on the engine's FileSystem: both seams (ActionCache, BlobStore) and what only
// a local cache has (locks, scratch directories, gc, verify).
class Cache final : public ActionCache, public BlobStore {
 public:
  Cache(FileSystem& fs, std::filesystem::path root);

  const std::filesystem::path& root() const { return root_; }
  std::filesystem::path blob_path(const std::string& hash) const;
  std::filesystem::path action_path(const std::string& key) const;

  // The result for `key` if it is valid (above; `outputs`: the stage's declared output name
  // patterns, empty = any name) and every blob it names is present (sizes checked).
  std::optional<ActionResult> lookup(const std::string& key,
                                     const std::vector<std::string>& outputs = {}) override;
  // Writes the entry for `key`; `durable` fsyncs it and its directory (false when a
  // DurableBatch makes a batch of entries durable at once). False (and `error`) on failure.
  bool store(const std::string& key, const ActionResult& result, bool durable = true,
             std::string* error = nullptr) override;
  // fsync of each entry and of each directory holding one (or holding a directory this cache
  // made); syncfs for more than kSyncEachMaxFiles entries.
  bool make_durable(const std::vector<std::string>& keys, std::string* error = nullptr) override;

  // Moves `file` into the CAS (a rename: the bytes are not copied), read-only, replacing any
  // blob of that name (which heals a damaged one). Its mtime is set just below the clock read
  // before that, so every later write to it (or to a hard link of it) is visible to
  // DigestCache. `durable` fsyncs it and its directories (false when a DurableBatch makes a
  // batch of blobs durable at once).
  std::optional<Digest> put_file(const std::filesystem::path& file, std::int64_t* known_at = nullptr,
                                 bool durable = true, std::string* error = nullptr,
                                 const std::optional<Digest>& known = std::nullopt) override;
  // A hard link where possible, else a copy (a copy's mtime is set as the blob's).
  bool materialize(const Digest& d, const std::filesystem::path& dest, bool verify = true,
                   std::int64_t* known_at = nullptr, std::string* error = nullptr) override;
  // As for action results: fsyncs of the blobs and their directories, or one syncfs.
  bool make_durable(const std::vector<Digest>& digests, std::string* error = nullptr) override;

  // Marks the root as a sylva cache (a CACHEDIR.TAG, https://bford.info/cachedir/, which also
  // keeps backup tools out), once; lock_for_build() calls it. `sylva clean --all` deletes only
  // a directory is_cache() accepts.
  void mark();
  // True if `dir` is a sylva cache: it has sylva's CACHEDIR.TAG, or (caches made before the
  // tag) holds nothing but cas/, ac/, locks/ and tmp/, with locks/.
  static bool is_cache(FileSystem& fs, const std::filesystem::path& dir);

  // Exclusive lock for running action `key` (other processes wait, then hit the cache).
  std::unique_ptr<FileLock> lock_action(const std::string& key);
  // Held (shared) by every build for its whole run, and exclusively by gc: eviction never
  // deletes a blob a running build is storing or publishing.
  std::unique_ptr<FileLock> lock_for_build();
  std::unique_ptr<FileLock> lock_for_gc();
  std::unique_ptr<FileLock> try_lock_for_gc();  // nullptr if a build is running
  // A fresh, empty scratch directory under tmp/.
  std::filesystem::path make_scratch_dir();

  CacheStats stats();
  // Bytes held by blobs (one stat per blob; no content is read).
  std::uint64_t blob_bytes();
  // Removes stale tmp/ entries (older than an hour), then evicts least recently used action
  // results until blobs referenced take at most `max_bytes` (0: keep all results), then deletes
  // every blob no remaining action result references.
  GcResult gc(std::uint64_t max_bytes);
  // Re-hashes every blob and deletes those whose content does not match; then deletes every
  // action result that is not valid for its key or names a missing blob.
  VerifyResult verify_all();

 private:
  // Creates the directory of `file` if it is missing, remembering each directory it made: its
  // own name is made durable with the next make_durable().
  bool make_parent(const std::filesystem::path& file, std::string* error);
  bool sync_files(const std::vector<std::filesystem::path>& files, std::string* error);

  FileSystem& fs_;
  std::filesystem::path root_;
  std::mutex dirs_mu_;
  std::set<std::filesystem::path> new_dirs_;  // made since the last make_durable()
};

}  // namespace sylva
