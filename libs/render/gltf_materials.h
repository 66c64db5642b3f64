// Private: a glTF's materials, their base-colour textures and the images under them, read into
// a Scene for the glTF loader (gltf_scene.cpp). Every failure throws SceneLoadError
// ("<file>: error: ...").
#pragma once

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "libs/fileio/file_source.h"
#include "libs/render/gltf_model.h"
#include "libs/render/scene.h"

namespace sylva::render::detail {

// KHR_texture_transform of a texture reference: uv' = offset + R(rotation) (scale * uv), the
// spec's translation * rotation * scale (rotation counter-clockwise: u' = c u - s v,
// v' = s u + c v).
struct UvTransform {
  bool identity = true;
  float offset[2] = {0, 0}, scale[2] = {1, 1}, rotation = 0;  // rotation in radians
  Vec2 apply(Vec2 uv) const {
    if (identity) return uv;
    const float u = uv.x() * scale[0], v = uv.y() * scale[1], c = std::cos(rotation), s = std::sin(rotation);
    return Vec2(offset[0] + c * u - s * v, offset[1] + s * u + c * v);
  }
};

// Where a material's base-colour texture reads its coordinates: the TEXCOORD_n set (the
// transform's texCoord when it names one) and the transform applied to them.
struct MaterialUv {
  int texcoord_set = 0;
  UvTransform transform;
};

// KHR_texture_transform of a texture reference (identity without one); the extension's texCoord,
// when it names one, replaces `texcoord_set`. Also used by stage import's glTF reader.
UvTransform texture_transform(const tinygltf::TextureInfo& info, int& texcoord_set);

// Every image must have decoded (tinygltf loads them with the file); all the missing ones are
// named in one message, with tinygltf's `warnings` about each, or "no such file <path>" for an
// external image (a URI relative to `base_dir`) that is not there.
void check_images(const GltfModel& in, const std::string& warnings, const std::filesystem::path& base_dir,
                  const fileio::FileSource& files);

// Appends the glTF's materials to scene.materials and the base-colour textures they use (each
// once, 8-bit RGBA, with its sampler state) to scene.textures; returns each material's MaterialUv.
std::vector<MaterialUv> load_materials(const GltfModel& in, Scene& scene);

}  // namespace sylva::render::detail
