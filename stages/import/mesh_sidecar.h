// The files beside a model (a .gltf's buffers and images, an .obj's .mtl and textures), read
// through a fileio::FileSource and confined to the model file's folder.
//
// A reference the file makes is resolved against the model's folder. A reference that would
// leave it (an absolute path, a Windows drive path "C:/bark.png" or "C:\bark.png", or one whose
// ".." climbs above the folder) is not followed: the file's base name is looked for beside the
// model instead, with a warning — Quaternius' .mtl files name the textures by the exporting
// machine's absolute paths, and the textures ship beside the model.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "libs/fileio/file_source.h"

namespace sylva::import {

class SidecarFiles final : public fileio::FileSource {
 public:
  // `files` and `warnings` must outlive this. `source` names the model in warnings.
  SidecarFiles(const fileio::FileSource& files, std::filesystem::path base_dir, std::string source,
               std::vector<std::string>& warnings);

  // `path`: a reference as the file wrote it, or already joined to the base folder (as tinygltf
  // and Assimp pass them). Reads resolve(path). Throws fileio::FileReadError.
  std::string read(const std::filesystem::path& path) const override;
  bool exists(const std::filesystem::path& path) const override;

  // Where `ref` is looked for (see the top of this file). Warns once per reference that is moved.
  std::filesystem::path resolve(const std::string& ref) const;
  const std::filesystem::path& base_dir() const { return base_dir_; }

 private:
  const fileio::FileSource& files_;
  std::filesystem::path base_dir_;
  std::string source_;
  std::vector<std::string>& warnings_;
  mutable std::set<std::string> warned_;
};

}  // namespace sylva::import
