// POSIX implementation of FileSystem. write/copy use temp + fsync + rename (+ fsync of the
// directory) so that a crash, a power loss or Ctrl-C never leaves a partial file under a name
// the engine trusts (Bazel's disk cache does the same); locks are flock(2), which the kernel
// drops when a process dies. Files are opened with O_NONBLOCK and checked with fstat before
// reading, so a FIFO or a device named where a file is expected is refused instead of blocking
// forever or streaming /dev/zero.
#include "pipeline/filesystem.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <system_error>

#include "libs/fileio/read_file.h"

namespace sylva {

namespace {

bool fail(std::string* error, int err = errno) {
  if (error) *error = std::strerror(err);
  return false;
}

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

// fsync of a directory: makes the entries just renamed into it survive a power loss.
bool sync_directory(const fs::path& dir) {
  int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}

// Opens a regular file for reading without blocking on a FIFO; -1 (errno or `*not_regular`)
// otherwise. `st` receives its fstat.
int open_regular(const fs::path& p, struct stat* st, std::string* error) {
  int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) {
    fail(error);
    return -1;
  }
  if (::fstat(fd, st) != 0) {
    fail(error);
    ::close(fd);
    return -1;
  }
  if (!S_ISREG(st->st_mode)) {
    if (error) *error = S_ISDIR(st->st_mode) ? "Is a directory" : "not a regular file";
    ::close(fd);
    return -1;
  }
  // Regular files ignore O_NONBLOCK; clear it anyway so reads behave as documented everywhere.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

// Writes through `fill` into a temp sibling of `p`, then renames it into place.
template <class Fill>
bool atomic_replace(const fs::path& p, Fill fill, bool durable, std::string* error) {
  std::error_code ec;
  if (p.has_parent_path()) fs::create_directories(p.parent_path(), ec);
  const fs::path tmp = unique_temp_path(p);
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return fail(error);
  int err = 0;
  bool ok = fill(fd);
  if (!ok) err = errno;
  if (ok && durable && ::fsync(fd) != 0) ok = false, err = errno;
  if (::close(fd) != 0 && ok) ok = false, err = errno;
  if (ok && ::rename(tmp.c_str(), p.c_str()) != 0) ok = false, err = errno;
  if (!ok) {
    ::unlink(tmp.c_str());
    return fail(error, err);
  }
  if (durable && !sync_directory(p.parent_path())) return fail(error);
  return true;
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

std::optional<std::string> RealFileSystem::read(const fs::path& p, std::string* error,
                                                std::uint64_t max_bytes) {
  return fileio::read_regular_file(p, error, max_bytes);
}

bool RealFileSystem::write_atomic(const fs::path& p, std::string_view bytes, bool durable,
                                  std::string* error) {
  return atomic_replace(
      p, [&](int fd) { return write_all(fd, bytes.data(), bytes.size()); }, durable, error);
}

bool RealFileSystem::copy_atomic(const fs::path& from, const fs::path& to, std::string* error) {
  struct stat st {};
  int in = open_regular(from, &st, error);
  if (in < 0) return false;
  bool ok = atomic_replace(
      to,
      [&](int fd) {
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
      },
      true, error);
  ::close(in);
  return ok;
}

namespace {
// A file written with plain write(2) calls; the caller (HashingStream) does the buffering.
class PosixWritableFile final : public WritableFile {
 public:
  explicit PosixWritableFile(int fd) : fd_(fd) {}
  ~PosixWritableFile() override {
    if (fd_ >= 0) ::close(fd_);
  }
  bool append(const char* data, std::size_t n, std::string* error) override {
    if (err_ == 0 && !write_all(fd_, data, n)) err_ = errno;
    return err_ == 0 || fail(error, err_);
  }
  bool close(std::string* error) override {
    if (fd_ < 0) return err_ == 0 || fail(error, err_);
    if (::close(fd_) != 0 && err_ == 0) err_ = errno;
    fd_ = -1;
    return err_ == 0 || fail(error, err_);
  }

 private:
  int fd_;
  int err_ = 0;
};
}  // namespace

std::unique_ptr<WritableFile> RealFileSystem::create(const fs::path& p, std::string* error) {
  const int fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    fail(error);
    return nullptr;
  }
  return std::make_unique<PosixWritableFile>(fd);
}

namespace {
FileInfo info_of(const struct stat& st) {
  FileInfo info;
  info.is_dir = S_ISDIR(st.st_mode);
  info.is_other = !info.is_dir && !S_ISREG(st.st_mode);
  info.size = static_cast<std::uint64_t>(st.st_size);
  info.mtime_ns = std::int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
  info.ctime_ns = std::int64_t(st.st_ctim.tv_sec) * 1000000000 + st.st_ctim.tv_nsec;
  info.ino = static_cast<std::uint64_t>(st.st_ino);
  info.dev = static_cast<std::uint64_t>(st.st_dev);
  return info;
}
}  // namespace

std::optional<FileInfo> RealFileSystem::stat(const fs::path& p) {
  struct stat st {};
  if (::stat(p.c_str(), &st) != 0) return std::nullopt;
  return info_of(st);
}

std::optional<FileInfo> RealFileSystem::stat_checking_link(const fs::path& p, bool* not_link) {
  struct stat st {};
  if (::lstat(p.c_str(), &st) != 0) {
    *not_link = true;  // nothing there, not even a dangling link
    return std::nullopt;
  }
  *not_link = !S_ISLNK(st.st_mode);
  if (*not_link) return info_of(st);
  return stat(p);
}

bool RealFileSystem::remove(const fs::path& p) {
  std::error_code ec;
  fs::remove(p, ec);
  return !fs::exists(fs::symlink_status(p, ec));
}

bool RealFileSystem::remove_all(const fs::path& p) {
  std::error_code ec;
  // CAS blobs are read-only; directories stay writable, so removal works without chmod.
  fs::remove_all(p, ec);
  return !ec;
}

bool RealFileSystem::make_dirs(const fs::path& p, std::string* error) {
  std::error_code ec;
  fs::create_directories(p, ec);
  if (fs::is_directory(p)) return true;
  if (error) *error = ec ? ec.message() : "Not a directory";
  return false;
}

std::vector<std::string> RealFileSystem::list(const fs::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    out.push_back(it->path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

namespace {
std::unique_ptr<FileLock> flock_path(const fs::path& p, int how) {
  std::error_code ec;
  if (p.has_parent_path()) fs::create_directories(p.parent_path(), ec);
  int fd = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return nullptr;
  while (::flock(fd, how) != 0) {
    if (errno != EINTR) {
      ::close(fd);
      return nullptr;
    }
  }
  return std::make_unique<FlockLock>(fd);
}
}  // namespace

std::unique_ptr<FileLock> RealFileSystem::lock(const fs::path& p) { return flock_path(p, LOCK_EX); }
std::unique_ptr<FileLock> RealFileSystem::lock_shared(const fs::path& p) { return flock_path(p, LOCK_SH); }
std::unique_ptr<FileLock> RealFileSystem::try_lock(const fs::path& p) {
  return flock_path(p, LOCK_EX | LOCK_NB);
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

std::optional<Digest> RealFileSystem::digest(const fs::path& p, std::string* error) {
  struct stat st {};
  int fd = open_regular(p, &st, error);
  if (fd < 0) return std::nullopt;
  // One buffer per thread, allocated once and never cleared: hashing a 60-byte file costs a
  // 60-byte read, not a fresh zeroed megabyte.
  constexpr std::size_t kChunk = 1 << 18;
  thread_local std::unique_ptr<char[]> buf(new char[kChunk]);
  Sha256 h;
  std::uint64_t total = 0;
  for (;;) {
    if (cancelled()) {  // every 256 KiB: Ctrl-C and SIGTERM stop a big hash within milliseconds
      ::close(fd);
      if (error) *error = "interrupted";
      return std::nullopt;
    }
    ssize_t n = ::read(fd, buf.get(), kChunk);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail(error);
      ::close(fd);
      return std::nullopt;
    }
    if (n == 0) break;
    h.update(buf.get(), static_cast<std::size_t>(n));
    total += static_cast<std::uint64_t>(n);
  }
  ::close(fd);
  return Digest{h.finish_hex(), total};
}

bool RealFileSystem::link_or_copy(const fs::path& from, const fs::path& to, bool* linked,
                                  std::string* error) {
  std::error_code ec;
  if (to.has_parent_path()) fs::create_directories(to.parent_path(), ec);
  const fs::path tmp = unique_temp_path(to);
  if (::link(from.c_str(), tmp.c_str()) == 0) {
    if (::rename(tmp.c_str(), to.c_str()) == 0) {
      if (linked) *linked = true;
      return true;
    }
    const int err = errno;
    ::unlink(tmp.c_str());
    return fail(error, err);
  }
  if (errno != EXDEV && errno != EPERM && errno != EMLINK && errno != ENOTSUP && errno != EOPNOTSUPP)
    return fail(error);
  // Another file system, or no hard links here: store a copy instead.
  if (linked) *linked = false;
  return copy_atomic(from, to, error);
}

bool RealFileSystem::sync(const fs::path& p, std::string* error) {
  int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return fail(error);
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    return fail(error, err);
  }
  if (::close(fd) != 0) return fail(error);
  return true;
}

bool RealFileSystem::rename(const fs::path& from, const fs::path& to, std::string* error) {
  if (::rename(from.c_str(), to.c_str()) == 0) return true;
  return fail(error);
}

void RealFileSystem::set_mtime(const fs::path& p, std::int64_t mtime_ns) {
  struct timespec times[2];
  times[0].tv_sec = 0;
  times[0].tv_nsec = UTIME_OMIT;
  times[1].tv_sec = static_cast<time_t>(mtime_ns / 1000000000);
  times[1].tv_nsec = static_cast<long>(mtime_ns % 1000000000);
  ::utimensat(AT_FDCWD, p.c_str(), times, 0);
}

std::int64_t RealFileSystem::now_ns() {
  struct timespec now {};
  ::clock_gettime(CLOCK_REALTIME_COARSE, &now);
  return std::int64_t(now.tv_sec) * 1000000000 + now.tv_nsec;
}

std::optional<std::uint64_t> RealFileSystem::free_bytes(const fs::path& p) {
  struct statvfs v {};
  fs::path at = p;
  std::error_code ec;
  while (!at.empty() && !fs::exists(at, ec)) at = at.parent_path();
  if (::statvfs(at.empty() ? "." : at.c_str(), &v) != 0) return std::nullopt;
  return static_cast<std::uint64_t>(v.f_bavail) * static_cast<std::uint64_t>(v.f_frsize);
}

bool RealFileSystem::replace_dir(const fs::path& staged, const fs::path& dest, fs::path* displaced,
                                 std::string* error) {
  if (displaced) displaced->clear();
  // Nothing there yet: a plain rename (fails if another publisher got there first; then swap).
  if (::renameat2(AT_FDCWD, staged.c_str(), AT_FDCWD, dest.c_str(), RENAME_NOREPLACE) == 0) return true;
  if (errno != EEXIST && errno != ENOTEMPTY && errno != EINVAL && errno != ENOSYS) return fail(error);
  if (::renameat2(AT_FDCWD, staged.c_str(), AT_FDCWD, dest.c_str(), RENAME_EXCHANGE) == 0) {
    if (displaced) *displaced = staged;  // now holds the old directory
    return true;
  }
  if (errno != EINVAL && errno != ENOSYS && errno != ENOENT) return fail(error);
  // No RENAME_EXCHANGE on this file system: move the old one aside, then the new one in.
  const fs::path old = unique_temp_path(staged);
  const bool had_old = ::rename(dest.c_str(), old.c_str()) == 0;
  if (!had_old && errno != ENOENT) return fail(error);
  if (::rename(staged.c_str(), dest.c_str()) != 0) {
    const int err = errno;
    if (had_old) ::rename(old.c_str(), dest.c_str());
    return fail(error, err);
  }
  if (had_old && displaced) *displaced = old;
  return true;
}

bool RealFileSystem::sync_fs(const fs::path& p, std::string* error) {
  fs::path at = p;
  std::error_code ec;
  while (!at.empty() && !fs::exists(at, ec)) at = at.parent_path();
  int fd = ::open(at.empty() ? "." : at.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return fail(error);
  if (::syncfs(fd) != 0) {
    const int err = errno;
    ::close(fd);
    return fail(error, err);
  }
  ::close(fd);
  return true;
}

std::optional<fs::path> RealFileSystem::real_path(const fs::path& p) {
  char* r = ::realpath(p.c_str(), nullptr);
  if (!r) return std::nullopt;
  fs::path out(r);
  ::free(r);
  return out;
}

}  // namespace sylva
