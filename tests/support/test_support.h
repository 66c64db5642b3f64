// Helpers shared by every test executable.
#pragma once

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

}  // namespace sylva::test
