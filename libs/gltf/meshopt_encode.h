// Private to libs/gltf: a built tinygltf model -> GLB bytes with EXT_meshopt_compression.
#pragma once

#include <cstddef>
#include <map>
#include <string>

namespace tinygltf {
class Model;
}

namespace sylva::gltf::detail {

// Every buffer view that holds one vertex attribute or one index accessor is encoded with
// meshoptimizer's codecs (ATTRIBUTES: the vertex codec; TRIANGLES: the index codec, version 1;
// INDICES: the index sequence codec for lines and points) into buffer 0, the GLB's binary chunk;
// the views themselves move to buffer 1, a fallback buffer without data
// ({"fallback": true}), so the extension is required. Image views stay uncompressed in buffer 0.
// `filters` names the meshopt filter of views whose bytes are already filtered (view index ->
// "OCTAHEDRAL", ...); such a view must be compressed. `merge`: views of the same kind, element
// type and filter are first concatenated into one view (WriteOptions::meshopt_merge_views).
// Deterministic. Throws GltfError.
std::string encode_meshopt_glb(tinygltf::Model& model, const std::map<int, std::string>& filters = {},
                               bool merge = false);

// One view's bytes through a meshoptimizer codec: kAttributes (the vertex codec; `stride` a
// multiple of 4, at most 252), kTriangles (the index codec, version 1; count a multiple of 3) or
// kIndices (the index sequence codec); indices are `stride` = 2 or 4 bytes. `data` holds count x
// stride bytes. Throws GltfError when the codec fails.
enum class MeshoptMode { kAttributes, kTriangles, kIndices };
std::string encode_meshopt_view(const unsigned char* data, MeshoptMode mode, std::size_t count,
                                std::size_t stride);

}  // namespace sylva::gltf::detail
