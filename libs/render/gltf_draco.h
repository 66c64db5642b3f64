// Private: KHR_draco_mesh_compression for the glTF loader (gltf_scene.cpp): decoding a
// primitive's Draco stream, and the workaround that lets Debian's tinygltf 2.7 read such files.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "libs/render/gltf_model.h"

namespace sylva::render::detail {

// A Draco-compressed primitive, decoded once: its attributes by glTF name, and its faces'
// indices when the stream is a mesh (a point cloud has none).
struct DracoData {
  std::map<std::string, AttributeData> attributes;
  std::vector<std::uint32_t> indices;  // 3 per face
  bool has_faces = false;
};

// Decodes the primitive's KHR_draco_mesh_compression object `ext` (meshes and point clouds,
// quantised attributes as floats). Throws SceneLoadError ("<file>: error: <what>: ...").
DracoData decode_draco(const GltfModel& in, const tinygltf::Value& ext, const std::string& what);

// Debian's tinygltf 2.7.0 rejects a primitive whose `indices` accessor has no bufferView
// ("accessor[N] invalid bufferView"), which is exactly how KHR_draco_mesh_compression primitives
// are written (the indices live in the Draco stream; fixed upstream in tinygltf PR #456, 2023).
// These drop `indices` from such primitives before tinygltf sees the JSON: the loader takes
// Draco primitives' indices from the decoded faces anyway.
//
// The glTF JSON `text` without them; nullopt when nothing changed or the JSON does not parse
// (tinygltf then reports the error).
std::optional<std::string> without_draco_index_accessors(const std::string& text);
// The same for a GLB container: rewrites its JSON chunk, keeps the binary chunk as it is.
void patch_glb(std::string& bytes);

}  // namespace sylva::render::detail
