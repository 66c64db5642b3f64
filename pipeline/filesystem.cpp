// POSIX implementation of FileSystem. write/copy use temp + fsync + rename so that a crash or
// Ctrl-C never leaves a partial file under a name the engine trusts (Bazel's disk cache does
// the same); locks are flock(2), which the kernel drops when a process dies.
#include "pipeline/filesystem.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <system_error>

namespace sylva {

namespace {

bool write_all(int fd, const char* data, std::size_t n) {
  while (n > 0) {
    ssize_t w = ::write(fd, data, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

// Writes through `fill` into a temp sibling of `p`, then renames it into place.
template <class Fill>
bool atomic_replace(const fs::path& p, Fill fill) {
  std::error_code ec;
  if (p.has_parent_path()) fs::create_directories(p.parent_path(), ec);
  const fs::path tmp = unique_temp_path(p);
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  bool ok = fill(fd) && ::fsync(fd) == 0;
  ok = (::close(fd) == 0) && ok;
  if (ok && ::rename(tmp.c_str(), p.c_str()) == 0) return true;
  ::unlink(tmp.c_str());
  return false;
}

class FlockLock final : public FileLock {
 public:
  explicit FlockLock(int fd) : fd_(fd) {}
  ~FlockLock() override {
    ::flock(fd_, LOCK_UN);
    ::close(fd_);
  }

 private:
  int fd_;
};

}  // namespace

fs::path unique_temp_path(const fs::path& p) {
  static std::atomic<std::uint64_t> counter{0};
  return fs::path(p.string() + ".tmp." + std::to_string(::getpid()) + "." +
                  std::to_string(counter.fetch_add(1)));
}

std::optional<std::string> RealFileSystem::read(const fs::path& p, std::string* error) {
  int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (error) *error = std::strerror(errno);
    return std::nullopt;
  }
  struct stat st {};
  if (::fstat(fd, &st) == 0 && S_ISDIR(st.st_mode)) {
    ::close(fd);
    if (error) *error = "Is a directory";
    return std::nullopt;
  }
  std::string out;
  char buf[1 << 16];
  for (;;) {
    ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (error) *error = std::strerror(errno);
      ::close(fd);
      return std::nullopt;
    }
    if (n == 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return out;
}

bool RealFileSystem::write_atomic(const fs::path& p, std::string_view bytes) {
  return atomic_replace(p, [&](int fd) { return write_all(fd, bytes.data(), bytes.size()); });
}

bool RealFileSystem::copy_atomic(const fs::path& from, const fs::path& to) {
  int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) return false;
  bool ok = atomic_replace(to, [&](int fd) {
    char buf[1 << 16];
    for (;;) {
      ssize_t n = ::read(in, buf, sizeof buf);
      if (n < 0) {
        if (errno == EINTR) continue;
        return false;
      }
      if (n == 0) return true;
      if (!write_all(fd, buf, static_cast<std::size_t>(n))) return false;
    }
  });
  ::close(in);
  return ok;
}

std::optional<FileInfo> RealFileSystem::stat(const fs::path& p) {
  struct stat st {};
  if (::stat(p.c_str(), &st) != 0) return std::nullopt;
  return FileInfo{S_ISDIR(st.st_mode), static_cast<std::uint64_t>(st.st_size)};
}

bool RealFileSystem::remove(const fs::path& p) {
  std::error_code ec;
  fs::remove(p, ec);
  return !fs::exists(p, ec);
}

bool RealFileSystem::remove_all(const fs::path& p) {
  std::error_code ec;
  // CAS blobs are read-only; directories stay writable, so removal works without chmod.
  fs::remove_all(p, ec);
  return !ec;
}

bool RealFileSystem::make_dirs(const fs::path& p) {
  std::error_code ec;
  fs::create_directories(p, ec);
  return fs::is_directory(p, ec);
}

std::vector<std::string> RealFileSystem::list(const fs::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    out.push_back(it->path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::unique_ptr<FileLock> RealFileSystem::lock(const fs::path& p) {
  std::error_code ec;
  if (p.has_parent_path()) fs::create_directories(p.parent_path(), ec);
  int fd = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return nullptr;
  while (::flock(fd, LOCK_EX) != 0) {
    if (errno != EINTR) {
      ::close(fd);
      return nullptr;
    }
  }
  return std::make_unique<FlockLock>(fd);
}

void RealFileSystem::make_read_only(const fs::path& p) { ::chmod(p.c_str(), 0444); }

void RealFileSystem::touch(const fs::path& p) { ::utimensat(AT_FDCWD, p.c_str(), nullptr, 0); }

std::optional<double> RealFileSystem::age_seconds(const fs::path& p) {
  struct stat st {};
  if (::stat(p.c_str(), &st) != 0) return std::nullopt;
  struct timespec now {};
  ::clock_gettime(CLOCK_REALTIME, &now);
  return static_cast<double>(now.tv_sec - st.st_mtim.tv_sec) +
         1e-9 * static_cast<double>(now.tv_nsec - st.st_mtim.tv_nsec);
}

}  // namespace sylva
