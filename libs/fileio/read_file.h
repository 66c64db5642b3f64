// The one reader of whole files from the disk, for the engine (RealFileSystem::read), every
// library that reads a file by path and every command: what is not a regular file (a FIFO, a
// device, a socket, a directory) is refused without blocking on it or streaming it, and so is a
// file larger than the caller's limit, without reading it. Plain C++ and POSIX; no dependencies.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

namespace sylva::fileio {

// The default limit of read_file(): larger files are not inputs sylva reads whole.
inline constexpr std::uint64_t kMaxFileBytes = std::uint64_t{1} << 34;  // 16 GiB

// The bytes of regular file `path`, at most `max_bytes` of them. nullopt and `why` (if given)
// otherwise: strerror(3) words ("No such file or directory", "Permission denied"), "Is a
// directory", "not a regular file" or "larger than N bytes".
std::optional<std::string> read_regular_file(const std::filesystem::path& path, std::string* why = nullptr,
                                             std::uint64_t max_bytes = kMaxFileBytes);

// what(): "<path>: error: <reason>" (the reasons above); reason() the reason alone.
class FileReadError : public std::runtime_error {
 public:
  FileReadError(const std::filesystem::path& path, std::string reason)
      : std::runtime_error(path.string() + ": error: " + reason), reason_(std::move(reason)) {}
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

// read_regular_file, throwing FileReadError.
std::string read_file(const std::filesystem::path& path, std::uint64_t max_bytes = kMaxFileBytes);

// True if `path` names something (it is not opened: a FIFO is not waited on).
bool exists(const std::filesystem::path& path);

}  // namespace sylva::fileio
