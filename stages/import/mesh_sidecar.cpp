// Confining a model's sidecar files to its folder (mesh_sidecar.h). Lexical only: the readers
// go through a FileSource, which may be the engine's declared files (no disk paths to resolve).
#include "stages/import/mesh_sidecar.h"

#include <algorithm>

namespace sylva::import {

namespace fs = std::filesystem;

namespace {

// A component like "C:": a Windows drive, meaningless on this machine.
bool has_drive(const fs::path& p) {
  return std::any_of(p.begin(), p.end(), [](const fs::path& c) {
    const std::string s = c.string();
    return s.size() == 2 && s[1] == ':';
  });
}

// True when `p` (lexically normal) lies inside `base` (lexically normal).
bool inside(const fs::path& p, const fs::path& base) {
  const fs::path rel = p.lexically_relative(base);
  return !rel.empty() && *rel.begin() != "..";
}

}  // namespace

SidecarFiles::SidecarFiles(const fileio::FileSource& files, fs::path base_dir, std::string source,
                           std::vector<std::string>& warnings)
    : files_(files),
      base_dir_(base_dir.empty() ? fs::path(".") : std::move(base_dir)),
      source_(std::move(source)),
      warnings_(warnings) {
  base_dir_ = base_dir_.lexically_normal();
}

fs::path SidecarFiles::resolve(const std::string& ref) const {
  std::string text = ref;
  std::replace(text.begin(), text.end(), '\\', '/');
  const fs::path raw(text);
  const fs::path joined = (raw.is_absolute() ? raw : base_dir_ / raw).lexically_normal();
  if (!has_drive(raw) && inside(joined, base_dir_)) return joined;
  const fs::path beside = base_dir_ / raw.filename();
  // The reference as the file wrote it: tinygltf and Assimp pass it joined to the model's folder
  // (tinygltf also as "./<ref>" when it looks again), which must not reach the import report (its
  // bytes do not depend on where the model lies), nor be warned about twice.
  const std::string folder = base_dir_.string() + "/";
  const std::string shown =
      fs::path(ref.rfind(folder, 0) == 0 ? ref.substr(folder.size()) : ref).lexically_normal().string();
  if (warned_.insert(shown).second)
    warnings_.push_back(source_ + ": warning: '" + shown +
                        "' is an absolute path or leaves the model's folder: looking for '" +
                        raw.filename().string() + "' beside the model instead");
  return beside;
}

std::string SidecarFiles::read(const fs::path& path) const { return files_.read(resolve(path.string())); }

bool SidecarFiles::exists(const fs::path& path) const { return files_.exists(resolve(path.string())); }

}  // namespace sylva::import
