// One mesh file -> SourceGeometry in sylva's frame: the reader for its format (glTF through
// tinygltf, mesh_gltf.h; the others through Assimp, mesh_assimp.h), then the checks every result
// goes through (mesh_checks.h), then the frame (mesh_frame.h). Pure but for the sidecar files,
// read through `files` and confined to the model's folder (mesh_sidecar.h).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "libs/fileio/file_source.h"
#include "stages/import/mesh_options.h"

namespace sylva::import {

// `format`: "gltf" (also .glb), "obj", "fbx", "dae", "3ds" or "ply". `path` is where the model
// lies (its folder is where sidecars are looked for); `source` names it in messages. The result's
// geometry passes tree::validate_source_geometry; facts say the unit, axis, counts and height.
// Throws MeshError ("<source>: error: ..."); std::invalid_argument for an unknown format.
MeshImport import_mesh(std::string bytes, std::string_view format, const std::filesystem::path& path,
                       std::string_view source, const fileio::FileSource& files, const MeshOptions& options);

}  // namespace sylva::import
