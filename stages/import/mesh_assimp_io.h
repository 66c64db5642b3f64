// Assimp's file access over sylva's files: the model's bytes, already read by the stage, under
// their own path, and every other file Assimp opens (an .obj's .mtl) through SidecarFiles, so a
// stage reads only what it declared and nothing leaves the model's folder (mesh_sidecar.h).
#pragma once

#include <assimp/IOSystem.hpp>
#include <string>

#include "stages/import/mesh_sidecar.h"

namespace sylva::import {

class AssimpFiles final : public Assimp::IOSystem {
 public:
  // `model` is served as `model_path`; `sidecars` must outlive this.
  AssimpFiles(std::string model_path, const std::string& model, const SidecarFiles& sidecars)
      : model_path_(std::move(model_path)), model_(model), sidecars_(sidecars) {}

  bool Exists(const char* path) const override;
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* path, const char* mode = "rb") override;
  void Close(Assimp::IOStream* stream) override;

 private:
  std::string model_path_;
  const std::string& model_;
  const SidecarFiles& sidecars_;
};

}  // namespace sylva::import
