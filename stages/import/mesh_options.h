// What a caller asks of the mesh readers (mesh_gltf.h, mesh_assimp.h) and what they hand back:
// the imported geometry in sylva's frame, the warnings about what the file did not say or said
// badly, and the facts the conversion used. docs/stages/import.md states these rules for users.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "libs/tree/source_geometry.h"

namespace sylva::import {

// The file's up axis. kAuto: the format's convention (glTF: Y; FBX: its GlobalSettings UpAxis;
// OBJ, 3DS, PLY, DAE: what Assimp reports, which is Y after its own conversion).
enum class MeshUp { kAuto, kY, kZ };

// The largest model file the stage reads (the stage passes it to read_param_file): a 100 MB
// tree reads; a file past it is refused before anything is parsed.
inline constexpr std::uint64_t kMaxMeshFileBytes = std::uint64_t(256) << 20;  // 256 MiB

struct MeshOptions {
  MeshUp up = MeshUp::kAuto;
  double scale = 1.0;    // multiplies after the file's unit is applied; > 0
  bool recenter = true;  // move the trunk foot to the origin (mesh_frame.h)
  std::string node;      // import only this node's subtree; "" = the whole default scene
  std::size_t max_vertices = tree::kMaxSourceVertices;    // over all primitives
  std::size_t max_triangles = tree::kMaxSourceTriangles;  // over all primitives
};

// What the conversion used, for the import report.
struct MeshFacts {
  std::string format;         // "gltf", "obj", "fbx", "dae", "3ds", "ply"
  std::string unit = "m";     // the file's unit as read ("m" when the format has none)
  double unit_scale = 1.0;    // file unit -> metres
  char up = 'y';              // the up axis used: 'y' or 'z'
  std::size_t vertices = 0;   // after the import
  std::size_t triangles = 0;  // after the import (degenerate faces dropped)
  double height = 0;          // m, max y - min y after the conversion
};

struct MeshImport {
  tree::SourceGeometry geometry;      // passes tree::validate_source_geometry
  std::vector<std::string> warnings;  // "<source>: warning: ...", in the order found
  MeshFacts facts;
};

// Bad input a reader cannot import. what(): "<source>: error: <element>: <problem>".
class MeshError : public std::runtime_error {
 public:
  MeshError(std::string_view source, std::string_view message)
      : std::runtime_error(std::string(source) + ": error: " + std::string(message)) {}
  // A message already in that form (a library's "<file>: error: ..." passed on).
  explicit MeshError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace sylva::import
