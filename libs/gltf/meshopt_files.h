// EXT_meshopt_compression over a set of .gltf files whose buffers are .bin files shared by uri
// (a forest's tile and level files: every tile of a species' level names that level's .bin).
// Lossless: every compressed view decodes to the bytes it held (a triangle's three indices
// possibly rotated, winding kept, as the index codec does), so each file draws what it drew
// before; the format is the one libs/gltf's GLB writer emits (writer.h "meshopt"),
// readable by three.js's MeshoptDecoder and Babylon.js.
//
// What is compressed: a buffer view that holds exactly one accessor (offset 0, count x element
// size = its length) used as a primitive attribute or an EXT_mesh_gpu_instancing attribute
// (ATTRIBUTES: element size a multiple of 4, at most 252 bytes), or as a primitive's indices
// (TRIANGLES for triangle lists, else INDICES; 2- or 4-byte indices) — in every file that views
// the same bytes (same .bin, offset and length), the same way, and that the codec makes smaller.
// Everything else (images, views used otherwise, views that overlap another, views the codec
// would not shrink) is copied raw.
//
// The layout of each new .bin: the distinct byte ranges the files view, in offset order, each
// compressed or raw, 4-byte aligned; bytes no file views are dropped. In each .gltf a compressed
// view moves to a fallback buffer (no uri, the original length, {"fallback": true}) at its old
// offset, with the extension pointing into the .bin; a raw view keeps the .bin at its new offset.
// Files already using EXT_meshopt_compression or KHR_draco_mesh_compression, or naming a buffer
// by a data: uri, are left as they are (and the .bin files they name are not rewritten).
// Deterministic: the output depends only on the input bytes and names.
#pragma once

#include <map>
#include <string>

namespace sylva::gltf {

struct GltfFileSet {
  std::map<std::string, std::string> gltf;  // file name -> JSON text
  std::map<std::string, std::string> bins;  // buffer uri -> bytes (every uri the files name)
};

struct MeshoptFilesStats {
  std::size_t views_compressed = 0, views_raw = 0;
  std::size_t bin_bytes_before = 0, bin_bytes_after = 0;  // over the rewritten .bin files
};

// The rewritten set (same names; .gltf text is dump(1) plus a newline). Throws GltfError naming
// the file when a .gltf is not JSON, names a buffer uri not in `bins`, or a view lies outside its
// buffer.
GltfFileSet meshopt_compress_files(const GltfFileSet& files, MeshoptFilesStats* stats = nullptr);

}  // namespace sylva::gltf
