// What sylva remembers between builds so that a no-op reads no file's content: per path, the
// stat (size, mtime, ctime, inode, device) the file had when its content was known to have a
// digest, as ninja's build log keeps output mtimes and Bazel's digest cache keeps
// (inode, mtime, ctime, size) -> digest. A file whose stat still matches is not read again.
// And per node, what it last published into this out dir (ninja's log line for an edge): the
// action it came from, its files and the stat of its directory.
//
// The racy-git rule: a record is kept only if the file's mtime is strictly older than the
// file-system clock (FileSystem::now_ns) read *before* its content was established. Any later
// write then gives the file a newer mtime, so a same-tick (same-second) edit can never hide
// behind an identical stat. Whole-second timestamps (nanoseconds 0) need two seconds of age.
// A write that also forges the old mtime changes ctime, which must match too. A record that
// fails the rule is not kept: the file is simply hashed again next time.
//
// Stored in <out>/<recipe>/.sylva/digests (binary, rewritten atomically when it changed); a
// missing or damaged file is an empty cache, never an error. Thread-safe.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "pipeline/cache.h"
#include "pipeline/digest.h"
#include "pipeline/filesystem.h"

namespace sylva {

// What node N last published into <out>/N/.
struct PublishedNode {
  std::string tag;                   // which action, from which cache: "<key> <cache root>"
  std::vector<OutputEntry> outputs;  // the files of <out>/N/, sorted by name (nothing else is there)
  FileInfo dir;                      // stat of <out>/N/ right after publishing (ino 0: unknown)
  std::string record_key;            // key of the action whose explain record was written
  friend bool operator==(const PublishedNode&, const PublishedNode&) = default;
};

class DigestCache {
 public:
  // `file` is where the records live; nothing is read until load().
  DigestCache(FileSystem& fs, std::filesystem::path file);

  void load();
  // Writes the records back if any changed. False (and `error`) if they could not be written.
  bool save(std::string* error = nullptr);

  // The digest of file `p`: the recorded one if its stat is unchanged, else hashed now (and
  // recorded). nullopt (and `error`) if it cannot be read. `known` is a stat of `p` the caller
  // already has (the recipe loader's), saving one stat call.
  std::optional<Digest> digest(const std::filesystem::path& p, std::string* error = nullptr,
                               const std::optional<FileInfo>& known = std::nullopt);
  // Directory digest: SHA-256 of the sorted "relative path \0 file hash \n" lines of every
  // regular file below `p`, each file through digest(). nullopt if unreadable, or if it holds
  // more than `max_files` regular files (error "holds more than N files"; found before any
  // file is hashed).
  std::optional<Digest> digest_dir(const std::filesystem::path& p, std::string* error = nullptr,
                                   std::size_t max_files = SIZE_MAX);

  // True if `p` is recorded with digest `d` and its stat is unchanged: it holds `d`, unread.
  bool holds(const std::filesystem::path& p, const Digest& d);
  // Records that `p` holds `d`, known since file-system time `known_at` (now_ns() taken before
  // the content was written or verified). Stats `p`; keeps nothing if the racy rule fails.
  void record(const std::filesystem::path& p, const Digest& d, std::int64_t known_at);
  void forget(const std::filesystem::path& p);
  // Publishing hard-links CAS blobs, and every new link of an inode changes its ctime, also under
  // the records of the other paths that are links of the same blob (two nodes with equal
  // outputs, a stage passing an input through). Called once at the end of a build, after its
  // last link: every record of an inode that record() saw this build, with the digest recorded
  // then and an unchanged size and mtime, takes the inode's current stat. Without it each build
  // would find those records stale and republish (and re-hash) their nodes, forever. The cost is
  // the window this build already trusts: an edit that forges mtime between a link and this
  // call goes unseen, as one between hashing and record() does.
  void settle_links();

  std::optional<PublishedNode> published(const std::string& node);
  void set_published(const std::string& node, PublishedNode p);
  void forget_published(const std::string& node);
  // The names of every node with a published record, sorted.
  std::vector<std::string> published_nodes();

  // The racy-git rule for one timestamp.
  static bool settled(std::int64_t mtime_ns, std::int64_t known_at);
  static bool same_file(const FileInfo& a, const FileInfo& b);

 private:
  struct Entry {
    FileInfo stat;
    Digest digest;
  };
  // The records as loaded, never copied out of the file's bytes (text_): a 10,000-node no-op
  // looks up ~20,000 of them once each, so building a map of them cost more than the lookups.
  // The file is written sorted, so they are found by binary search; each is decoded when asked.
  struct BaseEntry {
    std::string_view path;
    FileInfo stat;
    const char* hash;  // 32 raw bytes inside text_
    std::uint64_t size;
    std::size_t begin, end;  // the record's bytes in text_ (copied verbatim by save())
  };
  struct BaseNode {
    std::string_view name;
    std::size_t begin, end;
  };
  const BaseEntry* find_base(std::string_view path) const;            // mu_ held
  std::optional<Entry> find_entry(const std::string& path) const;     // mu_ held
  bool find_node(const std::string& node, PublishedNode* out) const;  // mu_ held

  FileSystem& fs_;
  std::filesystem::path file_;
  mutable std::mutex mu_;
  std::string text_;
  std::vector<BaseEntry> base_;
  std::vector<BaseNode> base_nodes_;
  // Changes since load(), by key; nullopt = removed. They shadow the base records.
  std::unordered_map<std::string, std::optional<Entry>> entries_;
  std::unordered_map<std::string, std::optional<PublishedNode>> nodes_;
  // Inodes record() saw this build ((dev, ino) -> the path and digest it recorded).
  std::map<std::pair<std::uint64_t, std::uint64_t>, std::pair<std::string, Digest>> linked_;
  bool dirty_ = false;
};

}  // namespace sylva
