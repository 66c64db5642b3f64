// Loading glTF 2.0 (.gltf with external or embedded buffers, or .glb) into a render::Scene.
//
// What is read (everything else is ignored; see docs/renderer.md):
//  - the default scene (or scene 0, or every root node when the file has no scenes), node
//    hierarchy with matrix or TRS transforms;
//  - EXT_mesh_gpu_instancing: per-instance TRANSLATION / ROTATION / SCALE accessors, applied
//    in the node's local space (world = node_world * T * R * S);
//  - primitives of every mode (strips, fans and loops are expanded), with POSITION, NORMAL,
//    TEXCOORD_n (the set the base-colour texture names), COLOR_0, and for POINTS the custom
//    attribute _SIZE (SCALAR float: point diameter in metres, local space);
//  - KHR_draco_mesh_compression primitives, decoded with the Draco library;
//  - KHR_mesh_quantization (integer and normalized accessors of any component type);
//  - KHR_texture_transform on the base colour texture (offset, rotation, scale, texCoord), applied
//    to the texture coordinates at load;
//  - materials: pbrMetallicRoughness.baseColorFactor and baseColorTexture (with its sampler),
//    alphaMode / alphaCutoff, doubleSided, KHR_materials_unlit.
//
// A file that lists any other extension in extensionsRequired is rejected.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "libs/fileio/file_source.h"
#include "libs/render/scene.h"

namespace sylva::render {

// The per-point size attribute of POINTS primitives: SCALAR, FLOAT, diameter in metres in the
// mesh's local space (scaled by the instance transform). Points without it are drawn with
// RenderOptions::default_point_size_px.
inline constexpr const char* kPointSizeAttribute = "_SIZE";

// Every loading failure. what() is one line: "<path>: error: <reason>", e.g.
//   "trees/oak.glb: error: texture 'bark.png' (image 0) could not be loaded: ..."
//   "trees/oak.glb: error: invalid glTF: ..."
class SceneLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Loads a .gltf or .glb file (detected by content, not extension). Throws SceneLoadError for
// unreadable files, invalid glTF, missing or undecodable textures, out-of-range indices or
// accessors, and undecodable Draco data; never crashes on bad input.
// The file and the files it names are read from `files`: the disk, or a stage's declared inputs.
Scene load_gltf_scene(const std::filesystem::path& path,
                      const fileio::FileSource& files = fileio::disk_files());

// The same from the bytes of a .glb or .gltf held in memory (a file just encoded, say). `name`
// stands for the file in messages; external uris resolve against `base_dir`.
Scene load_gltf_scene_from_memory(std::string bytes, const std::string& name,
                                  const std::filesystem::path& base_dir = {},
                                  const fileio::FileSource& files = fileio::disk_files());

}  // namespace sylva::render
