// Helpers shared by every test executable.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

namespace sylva::test {

// A fresh directory under the system temp dir, removed (recursively) on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& rel) const { return path_ / rel; }

 private:
  std::filesystem::path path_;
};

// ../shared/data (or $SYLVA_DATA_DIR) if it exists. Tests that need it call
//   auto data = sylva::test::data_dir(); if (!data) GTEST_SKIP() << "no test data";
std::optional<std::filesystem::path> data_dir();

std::string read_file(const std::filesystem::path& p);
void write_file(const std::filesystem::path& p, const std::string& bytes);

// Marsaglia's xorshift64 (shifts 13, 7, 17): the deterministic stream of the fuzz-style tests.
// `seed` must not be 0.
class XorShift64 {
 public:
  explicit XorShift64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t operator()() {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 7;
    state_ ^= state_ << 17;
    return state_;
  }

 private:
  std::uint64_t state_;
};

// All that was written to `f` (a std::tmpfile() a command printed to), read from its start; closes
// `f`.
std::string read_and_close(std::FILE* f);

}  // namespace sylva::test
