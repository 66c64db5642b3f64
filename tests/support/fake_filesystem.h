// An in-memory FileSystem for tests: records every write and can be told to fail writes whose
// path contains a given substring (to prove that failures leave nothing half-written).
#pragma once

#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "pipeline/filesystem.h"

namespace sylva::test {

class FakeFileSystem final : public FileSystem {
 public:
  std::map<std::string, std::string> files;    // path -> content
  std::map<std::string, double> ages;          // path -> seconds since modified (default 0)
  std::vector<std::string> writes;             // every successful write_atomic/copy target
  std::string fail_writes_containing;          // non-empty: such writes fail

  std::optional<std::string> read(const fs::path& p, std::string* error) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    auto it = files.find(p.lexically_normal().string());
    if (it == files.end()) {
      if (error) *error = "No such file or directory";
      return std::nullopt;
    }
    return it->second;
  }
  bool write_atomic(const fs::path& p, std::string_view bytes) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = p.lexically_normal().string();
    if (!fail_writes_containing.empty() && k.find(fail_writes_containing) != std::string::npos) return false;
    files[k] = std::string(bytes);
    ages[k] = 0;
    writes.push_back(k);
    return true;
  }
  bool copy_atomic(const fs::path& from, const fs::path& to) override {
    auto b = read(from, nullptr);
    return b && write_atomic(to, *b);
  }
  std::optional<FileInfo> stat(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = p.lexically_normal().string();
    if (auto it = files.find(k); it != files.end()) return FileInfo{false, it->second.size()};
    for (const auto& [f, c] : files)
      if (f.size() > k.size() && f.compare(0, k.size(), k) == 0 && f[k.size()] == '/') return FileInfo{true, 0};
    return std::nullopt;
  }
  bool remove(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    files.erase(p.lexically_normal().string());
    return true;
  }
  bool remove_all(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = p.lexically_normal().string();
    for (auto it = files.begin(); it != files.end();)
      it = (it->first == k || it->first.rfind(k + "/", 0) == 0) ? files.erase(it) : std::next(it);
    return true;
  }
  bool make_dirs(const fs::path&) override { return true; }
  std::vector<std::string> list(const fs::path& dir) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = dir.lexically_normal().string() + "/";
    std::set<std::string> names;
    for (const auto& [f, c] : files)
      if (f.rfind(k, 0) == 0) names.insert(f.substr(k.size(), f.find('/', k.size()) - k.size()));
    return {names.begin(), names.end()};
  }
  std::unique_ptr<FileLock> lock(const fs::path&) override { return std::make_unique<FileLock>(); }
  void make_read_only(const fs::path&) override {}
  void touch(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    ages[p.lexically_normal().string()] = 0;
  }
  std::optional<double> age_seconds(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = p.lexically_normal().string();
    if (auto it = ages.find(k); it != ages.end()) return it->second;
    return stat(p) ? std::optional<double>(0.0) : std::nullopt;
  }

 private:
  std::recursive_mutex mu_;
};

}  // namespace sylva::test
