// The content-addressed cache (Bazel's vocabulary), shared safely by concurrent builds:
//   <root>/cas/ab/<hash>     output blobs, named by their SHA-256, read-only
//   <root>/ac/ab/<key>       action results: JSON manifest of output name -> digest
//   <root>/locks/ab/<key>    flock files: one process runs an action at a time
//   <root>/tmp/              temporary files and stage scratch directories
// Every write is temp + fsync + rename. An action-cache hit counts only if every blob it
// names is present with the recorded size; a blob whose content does not hash to its name is
// deleted when it is read and the action rebuilt, never used.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/digest.h"
#include "pipeline/filesystem.h"

namespace sylva {

struct OutputEntry {
  std::string name;  // file name within the node's output directory
  Digest digest;
};

struct ActionResult {
  std::vector<OutputEntry> outputs;  // sorted by name
  std::string to_json() const;
  static std::optional<ActionResult> from_json(const std::string& text);
};

struct CacheStats {
  std::uint64_t blobs = 0, blob_bytes = 0, actions = 0, tmp_entries = 0;
};

struct GcResult {
  std::uint64_t actions_removed = 0, blobs_removed = 0, bytes_freed = 0, tmp_removed = 0;
};

class Cache {
 public:
  Cache(FileSystem& fs, std::filesystem::path root);

  const std::filesystem::path& root() const { return root_; }
  std::filesystem::path blob_path(const std::string& hash) const;
  std::filesystem::path action_path(const std::string& key) const;

  // The result for `key` if it and every blob it names are present (sizes checked).
  std::optional<ActionResult> lookup(const std::string& key);
  void store_action(const std::string& key, const ActionResult& result);

  // Hashes `file` and moves it into the CAS (a rename: the bytes are not copied), read-only,
  // replacing any blob of that name. Its mtime is set just below the clock read before hashing,
  // so every later write to it (or to a hard link of it) is visible to DigestCache.
  // `known_at` (if given) receives that clock value. The file is gone afterwards.
  std::optional<Digest> put_file(const std::filesystem::path& file, std::int64_t* known_at = nullptr);

  // Makes `dest` hold blob `d`: a hard link where possible (bytes stored once), else a copy;
  // atomically. With `verify`, the blob is hashed first, and one that does not match its
  // digest is deleted and false returned (the caller rebuilds). `known_at` receives the clock
  // read before the content was verified (for DigestCache::record).
  bool materialize(const Digest& d, const std::filesystem::path& dest, bool verify = true,
                   std::int64_t* known_at = nullptr);

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
  // Re-hashes every blob; deletes those whose content does not match. Returns the number removed.
  std::uint64_t verify_all();

 private:
  FileSystem& fs_;
  std::filesystem::path root_;
};

}  // namespace sylva
