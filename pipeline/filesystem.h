// The engine's only door to the disk. RealFileSystem is wired in the CLI; tests use it on
// temporary directories or the in-memory fake (tests/support/fake_filesystem.h) to inject faults.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace sylva {

namespace fs = std::filesystem;

struct FileInfo {
  bool is_dir = false;
  std::uint64_t size = 0;
};

// Held while a cross-process lock is owned; released on destruction.
class FileLock {
 public:
  virtual ~FileLock() = default;
};

class FileSystem {
 public:
  virtual ~FileSystem() = default;

  // Whole-file read; nullopt (and `error` set to the reason, e.g. "No such file or directory")
  // when it cannot be read.
  virtual std::optional<std::string> read(const fs::path& p, std::string* error = nullptr) = 0;
  // Writes `bytes` to a temporary sibling, fsyncs, and renames it over `p`: readers see the old
  // file or the new one, never a partial one. Creates parent directories. False on failure.
  virtual bool write_atomic(const fs::path& p, std::string_view bytes) = 0;
  // Copies `from` to `to` atomically (temp + fsync + rename). False on failure.
  virtual bool copy_atomic(const fs::path& from, const fs::path& to) = 0;
  virtual std::optional<FileInfo> stat(const fs::path& p) = 0;
  virtual bool remove(const fs::path& p) = 0;          // file or empty dir; true if gone
  virtual bool remove_all(const fs::path& p) = 0;      // recursive; true if gone
  virtual bool make_dirs(const fs::path& p) = 0;
  virtual std::vector<std::string> list(const fs::path& dir) = 0;  // entry names, sorted
  // Blocks until an exclusive advisory lock on `p` (created if needed) is held.
  virtual std::unique_ptr<FileLock> lock(const fs::path& p) = 0;
  // Marks a file read-only (CAS blobs), best effort.
  virtual void make_read_only(const fs::path& p) = 0;
  // Updates the modification time to now (LRU for cache gc), best effort.
  virtual void touch(const fs::path& p) = 0;
  // Seconds since the file was last modified (nullopt if absent).
  virtual std::optional<double> age_seconds(const fs::path& p) = 0;
};

class RealFileSystem final : public FileSystem {
 public:
  std::optional<std::string> read(const fs::path& p, std::string* error) override;
  bool write_atomic(const fs::path& p, std::string_view bytes) override;
  bool copy_atomic(const fs::path& from, const fs::path& to) override;
  std::optional<FileInfo> stat(const fs::path& p) override;
  bool remove(const fs::path& p) override;
  bool remove_all(const fs::path& p) override;
  bool make_dirs(const fs::path& p) override;
  std::vector<std::string> list(const fs::path& dir) override;
  std::unique_ptr<FileLock> lock(const fs::path& p) override;
  void make_read_only(const fs::path& p) override;
  void touch(const fs::path& p) override;
  std::optional<double> age_seconds(const fs::path& p) override;
};

// A name for a temporary sibling of `p` that no other thread or process uses.
fs::path unique_temp_path(const fs::path& p);

}  // namespace sylva
