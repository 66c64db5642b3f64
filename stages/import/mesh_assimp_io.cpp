// Assimp's IOSystem over the model's bytes and its sidecars (mesh_assimp_io.h). Streams copy
// the bytes they serve (MemoryIOStream owning a buffer): Assimp closes them at its own pace.
#include "stages/import/mesh_assimp_io.h"

#include <assimp/MemoryIOWrapper.h>

#include <cstring>

namespace sylva::import {

namespace {

Assimp::IOStream* stream_of(const std::string& bytes) {
  auto* copy = new uint8_t[bytes.size() + 1];
  std::memcpy(copy, bytes.data(), bytes.size());
  return new Assimp::MemoryIOStream(copy, bytes.size(), /*own=*/true);
}

}  // namespace

bool AssimpFiles::Exists(const char* path) const {
  if (path == model_path_) return true;
  return sidecars_.exists(path);
}

Assimp::IOStream* AssimpFiles::Open(const char* path, const char* mode) {
  if (mode == nullptr || std::strchr(mode, 'w') != nullptr || std::strchr(mode, 'a') != nullptr)
    return nullptr;
  if (path == model_path_) return stream_of(model_);
  if (!sidecars_.exists(path)) return nullptr;
  try {
    return stream_of(sidecars_.read(path));
  } catch (const std::exception&) {
    return nullptr;
  }
}

void AssimpFiles::Close(Assimp::IOStream* stream) { delete stream; }

}  // namespace sylva::import
