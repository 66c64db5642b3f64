// The engine's only door to the disk. RealFileSystem is wired in the CLI; tests use it on
// temporary directories or the in-memory fake (tests/support/fake_filesystem.h) to inject faults.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/digest.h"

namespace sylva {

namespace fs = std::filesystem;

// What stat(2) says about a file: enough to tell, without reading it, that it has not changed
// since it was last hashed (ninja's build log and Bazel's digest cache keep the same facts).
struct FileInfo {
  bool is_dir = false;
  bool is_other = false;  // neither a regular file nor a directory (FIFO, device, socket)
  std::uint64_t size = 0;
  std::int64_t mtime_ns = 0;  // content modification time, ns since the epoch
  std::int64_t ctime_ns = 0;  // inode change time (any write, chmod, link, rename of the inode)
  std::uint64_t ino = 0, dev = 0;
  friend bool operator==(const FileInfo&, const FileInfo&) = default;
};

// Held while a cross-process lock is owned; released on destruction.
class FileLock {
 public:
  virtual ~FileLock() = default;
};

// A regular file being written from the start (FileSystem::create): the caller buffers, this
// writes. Not atomic: it is for files in a private scratch directory, renamed into place later.
class WritableFile {
 public:
  virtual ~WritableFile() = default;  // closes the file if close() was not called
  // Appends `n` bytes. False (and `error`, strerror(3) words) if the write failed; the file is
  // then incomplete and every later append fails too.
  virtual bool append(const char* data, std::size_t n, std::string* error = nullptr) = 0;
  // Closes the file. False (and `error`) if closing failed (a delayed write error).
  virtual bool close(std::string* error = nullptr) = 0;
};

class FileSystem {
 public:
  virtual ~FileSystem() = default;

  // Errors: functions that can fail take an optional `error`, set to the reason as strerror(3)
  // words ("No space left on device", "Read-only file system") when they return false/nullopt.

  // Whole-file read of a regular file of at most `max_bytes` bytes; nullopt (and `error`) when
  // it cannot be read. A FIFO, device or socket is refused without blocking ("not a regular
  // file"), a larger file without reading it ("larger than N bytes").
  virtual std::optional<std::string> read(const fs::path& p, std::string* error = nullptr,
                                          std::uint64_t max_bytes = UINT64_MAX) = 0;
  // Writes `bytes` to a temporary sibling, fsyncs it and its directory after renaming it over
  // `p`: readers see the old file or the new one, never a partial one, and after a power loss
  // the new one. Creates parent directories. False (and `error`) on failure, leaving no
  // temporary file. `durable` false skips both fsyncs (files that are only caches or reports:
  // after a power loss they may be old or missing, never partial under their name).
  virtual bool write_atomic(const fs::path& p, std::string_view bytes, bool durable = true,
                            std::string* error = nullptr) = 0;
  // Copies `from` to `to` atomically (temp + fsync + rename). False on failure.
  virtual bool copy_atomic(const fs::path& from, const fs::path& to, std::string* error = nullptr) = 0;
  // Creates (or truncates) regular file `p` for writing, mode 0644; its directory must exist.
  // nullptr (and `error`) on failure.
  virtual std::unique_ptr<WritableFile> create(const fs::path& p, std::string* error = nullptr) = 0;
  virtual std::optional<FileInfo> stat(const fs::path& p) = 0;
  // stat(p), and *not_link = true if this call also established, on the real disk, that `p`
  // itself is not a symbolic link (or does not exist), which ProjectRoot::contains would
  // otherwise check with an lstat of its own. The default establishes nothing (false).
  virtual std::optional<FileInfo> stat_checking_link(const fs::path& p, bool* not_link) {
    *not_link = false;
    return stat(p);
  }
  virtual bool remove(const fs::path& p) = 0;      // file or empty dir; true if gone
  virtual bool remove_all(const fs::path& p) = 0;  // recursive; true if gone
  virtual bool make_dirs(const fs::path& p, std::string* error = nullptr) = 0;
  virtual std::vector<std::string> list(const fs::path& dir) = 0;  // entry names, sorted
  // Blocks until an exclusive advisory lock on `p` (created if needed) is held.
  virtual std::unique_ptr<FileLock> lock(const fs::path& p) = 0;
  // Marks a file read-only (CAS blobs), best effort.
  virtual void make_read_only(const fs::path& p) = 0;
  // Updates the modification time to now (LRU for cache gc), best effort.
  virtual void touch(const fs::path& p) = 0;
  // Seconds since the file was last modified (nullopt if absent).
  virtual std::optional<double> age_seconds(const fs::path& p) = 0;

  // SHA-256 and size of a regular file's content, streamed (never the whole file in memory);
  // nullopt (and `error`) if it cannot be read, is not a regular file, or the cancellation flag
  // (set_cancel_flag) was raised while hashing ("interrupted").
  virtual std::optional<Digest> digest(const fs::path& p, std::string* error = nullptr) = 0;
  // Makes `to` name the same bytes as `from`: a hard link where the file system allows it
  // (store once), else a copy; atomically (temporary sibling, then rename). `linked` says which.
  virtual bool link_or_copy(const fs::path& from, const fs::path& to, bool* linked = nullptr,
                            std::string* error = nullptr) = 0;
  // fsync(2) of an existing file, or of a directory (its entries: names renamed or linked into
  // it survive a power loss once it returns).
  virtual bool sync(const fs::path& p, std::string* error = nullptr) = 0;
  // rename(2): atomically replaces `to`. False on failure.
  virtual bool rename(const fs::path& from, const fs::path& to, std::string* error = nullptr) = 0;
  // Sets the modification time (ns since the epoch), best effort.
  virtual void set_mtime(const fs::path& p, std::int64_t mtime_ns) = 0;
  // A shared advisory lock (many holders; excludes lock()/try_lock()). Blocks; nullptr on error.
  virtual std::unique_ptr<FileLock> lock_shared(const fs::path& p) = 0;
  // The exclusive lock if it is free now, else nullptr (never blocks).
  virtual std::unique_ptr<FileLock> try_lock(const fs::path& p) = 0;
  // The clock file timestamps are taken from (CLOCK_REALTIME_COARSE), ns since the epoch: a
  // file written after now_ns() returned has a timestamp >= its value (the racy-git rule).
  virtual std::int64_t now_ns() = 0;
  // Free bytes for unprivileged users on the file system holding `p` (nullopt if unknown).
  virtual std::optional<std::uint64_t> free_bytes(const fs::path& p) = 0;

  // Makes directory `staged` appear at `dest` in one step: readers see the old directory or
  // the new one, never a mix (renameat2 RENAME_EXCHANGE; where the file system lacks it, two
  // renames with a moment in which `dest` is absent). If `dest` existed, its old directory is
  // left at `*displaced` (a temporary sibling) for the caller to remove. Both must be siblings.
  virtual bool replace_dir(const fs::path& staged, const fs::path& dest, fs::path* displaced,
                           std::string* error = nullptr) = 0;
  // syncfs(2): every write to the file system holding `p` so far is durable when it returns,
  // other processes' writes too (cheaper than an fsync per file only for many files).
  virtual bool sync_fs(const fs::path& p, std::string* error = nullptr) = 0;
  // The path with every symlink resolved (realpath(3)); nullopt if it does not exist.
  virtual std::optional<fs::path> real_path(const fs::path& p) = 0;
  // While *flag is true, digest() stops with "interrupted" (Ctrl-C must not wait for a
  // gigabyte to be hashed). nullptr: never.
  void set_cancel_flag(const std::atomic<bool>* flag) { cancel_ = flag; }

 protected:
  bool cancelled() const { return cancel_ && cancel_->load(std::memory_order_relaxed); }

 private:
  const std::atomic<bool>* cancel_ = nullptr;
};

class RealFileSystem final : public FileSystem {
 public:
  std::optional<std::string> read(const fs::path& p, std::string* error = nullptr,
                                  std::uint64_t max_bytes = UINT64_MAX) override;
  bool write_atomic(const fs::path& p, std::string_view bytes, bool durable = true,
                    std::string* error = nullptr) override;
  bool copy_atomic(const fs::path& from, const fs::path& to, std::string* error = nullptr) override;
  std::unique_ptr<WritableFile> create(const fs::path& p, std::string* error = nullptr) override;
  std::optional<FileInfo> stat(const fs::path& p) override;
  // One lstat; a second call (stat) only for a symbolic link.
  std::optional<FileInfo> stat_checking_link(const fs::path& p, bool* not_link) override;
  bool remove(const fs::path& p) override;
  bool remove_all(const fs::path& p) override;
  bool make_dirs(const fs::path& p, std::string* error = nullptr) override;
  std::vector<std::string> list(const fs::path& dir) override;
  std::unique_ptr<FileLock> lock(const fs::path& p) override;
  void make_read_only(const fs::path& p) override;
  void touch(const fs::path& p) override;
  std::optional<double> age_seconds(const fs::path& p) override;
  std::optional<Digest> digest(const fs::path& p, std::string* error = nullptr) override;
  bool link_or_copy(const fs::path& from, const fs::path& to, bool* linked = nullptr,
                    std::string* error = nullptr) override;
  bool sync(const fs::path& p, std::string* error = nullptr) override;
  bool rename(const fs::path& from, const fs::path& to, std::string* error = nullptr) override;
  void set_mtime(const fs::path& p, std::int64_t mtime_ns) override;
  std::unique_ptr<FileLock> lock_shared(const fs::path& p) override;
  std::unique_ptr<FileLock> try_lock(const fs::path& p) override;
  std::int64_t now_ns() override;
  std::optional<std::uint64_t> free_bytes(const fs::path& p) override;
  bool replace_dir(const fs::path& staged, const fs::path& dest, fs::path* displaced,
                   std::string* error = nullptr) override;
  bool sync_fs(const fs::path& p, std::string* error = nullptr) override;
  std::optional<fs::path> real_path(const fs::path& p) override;
};

// A name for a temporary sibling of `p` that no other thread or process uses.
fs::path unique_temp_path(const fs::path& p);

}  // namespace sylva
