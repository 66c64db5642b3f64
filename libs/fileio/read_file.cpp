// Why open with O_NONBLOCK and fstat before reading: an open(2) of a FIFO blocks until a writer
// comes, and a read of /dev/zero never ends; the descriptor's own fstat (not a stat of the path
// first, which a rename could outdate) decides what was opened.
#include "libs/fileio/read_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace sylva::fileio {

namespace {

bool fail(std::string* why, const std::string& reason) {
  if (why) *why = reason;
  return false;
}

}  // namespace

std::optional<std::string> read_regular_file(const std::filesystem::path& path, std::string* why,
                                             std::uint64_t max_bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) {
    fail(why, std::strerror(errno));
    return std::nullopt;
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    fail(why, std::strerror(errno));
    return std::nullopt;
  }
  if (!S_ISREG(st.st_mode)) {
    fail(why, S_ISDIR(st.st_mode) ? "Is a directory" : "not a regular file");
    return std::nullopt;
  }
  const std::string too_large = "larger than " + std::to_string(max_bytes) + " bytes";
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
    fail(why, too_large);
    return std::nullopt;
  }
  // Regular files ignore O_NONBLOCK; clear it anyway so reads behave as documented everywhere.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string out;
  out.reserve(static_cast<std::size_t>(st.st_size));
  char buf[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail(why, std::strerror(errno));
      return std::nullopt;
    }
    if (n == 0) break;
    out.append(buf, static_cast<std::size_t>(n));
    if (out.size() > max_bytes) {  // grew while being read
      fail(why, too_large);
      return std::nullopt;
    }
  }
  return out;
}

std::string read_file(const std::filesystem::path& path, std::uint64_t max_bytes) {
  std::string why;
  auto bytes = read_regular_file(path, &why, max_bytes);
  if (!bytes) throw FileReadError(path, why);
  return std::move(*bytes);
}

bool exists(const std::filesystem::path& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

}  // namespace sylva::fileio
