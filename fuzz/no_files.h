// A FileSource that holds no files, for the mesh fuzz targets: a model's sidecar references
// (buffers, .mtl, textures) all read as missing, so only the fuzzed bytes reach the readers.
#pragma once

#include <filesystem>
#include <string>

#include "libs/fileio/file_source.h"

namespace sylva::fuzz {

class NoFiles final : public fileio::FileSource {
 public:
  std::string read(const std::filesystem::path& path) const override {
    throw fileio::FileReadError(path, "no such file");
  }
  bool exists(const std::filesystem::path&) const override { return false; }
};

}  // namespace sylva::fuzz
