// Test helper: .gltf files sharing .bin buffers as a forest writes them (a species' level file
// and a tile file that instances its mesh), in memory, for the tests of meshopt_files.h and of
// the renderer's reading of the compressed files. Not part of libs/gltf's API; linked only by
// tests (sylva_gltf_testing).
#pragma once

#include "libs/gltf/meshopt_files.h"

namespace sylva::gltf::testing {

// "level.gltf" + "level.bin": one mesh drawn by one root node — a wavy grid of 30 x 30 quads
// (triangles with normals and uvs) and a 39-segment polyline (LINES) — and "tile.gltf" +
// "tile.bin": the level's JSON with its node instancing the mesh `instances` times
// (EXT_mesh_gpu_instancing TRANSLATION (10 i, 0, 3 i) from "tile.bin", its buffer 1).
GltfFileSet level_and_tile(int instances = 3);

}  // namespace sylva::gltf::testing
