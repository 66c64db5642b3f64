#include "libs/gltf/tinygltf_files.h"

namespace sylva::gltf {

namespace {

bool exists(const std::string& path, void* user) {
  return static_cast<const fileio::FileSource*>(user)->exists(path);
}

bool read_whole(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  try {
    const std::string bytes = static_cast<const fileio::FileSource*>(user)->read(path);
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const fileio::FileReadError& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}

}  // namespace

tinygltf::FsCallbacks file_callbacks(const fileio::FileSource& files) {
  return {&exists, &tinygltf::ExpandFilePath, &read_whole, &tinygltf::WriteWholeFile,
          const_cast<fileio::FileSource*>(&files)};
}

}  // namespace sylva::gltf
