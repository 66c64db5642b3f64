// The project root a recipe is confined to (docs/recipes.md, "Project root"): every file or
// directory a recipe names (`include:`, `!include`, path and directory parameters) must lie
// inside it once symbolic links are resolved, so a recipe from an untrusted pull request cannot
// read /etc/shadow or ~/.ssh and leak it through an error message or an output. A recipe may
// declare several roots (its sources, and a data directory elsewhere).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace sylva {

class ProjectRoot {
 public:
  // Unconfined: every path is allowed (--allow-outside-root, for trusted recipes).
  ProjectRoot() = default;
  // Confined to `dirs` (each made absolute, symbolic links resolved); at least one.
  explicit ProjectRoot(const std::vector<std::filesystem::path>& dirs);
  explicit ProjectRoot(const std::filesystem::path& dir)
      : ProjectRoot(std::vector<std::filesystem::path>{dir}) {}

  bool confined() const { return confined_; }
  const std::vector<std::filesystem::path>& dirs() const { return dirs_; }
  // True if `p` (absolute or relative to the working directory; it need not
  // exist) is one of the dirs or below one after resolving the symbolic links of its existing
  // part. Each directory is resolved once per ProjectRoot (and its copies): a recipe naming
  // 10,000 files in one directory costs one lstat per file, not a readlink per path element
  // (the working directory must not change while a ProjectRoot is in use).
  // `known_not_link`: the caller already established (FileSystem::stat_checking_link) that
  // the last element of `p` is not a symbolic link, saving that lstat. Thread-safe.
  bool contains(const std::filesystem::path& p, bool known_not_link = false) const;
  // "'P' is outside the project root 'D' (...how to allow it...)", for a diagnostic.
  std::string outside_message(const std::filesystem::path& p) const;

 private:
  struct DirCache;  // resolved directories, shared by copies
  bool confined_ = false;
  std::vector<std::filesystem::path> dirs_;
  std::vector<std::string> dir_strings_;  // dirs_ without a trailing "/"
  std::shared_ptr<DirCache> resolved_dirs_;
};

}  // namespace sylva
