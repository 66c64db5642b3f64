// The mesh import's recipe (mesh_import.h): read, check, move into sylva's frame.
#include "stages/import/mesh_import.h"

#include "stages/import/mesh_assimp.h"
#include "stages/import/mesh_checks.h"
#include "stages/import/mesh_frame.h"
#include "stages/import/mesh_gltf.h"

namespace sylva::import {

MeshImport import_mesh(std::string bytes, std::string_view format, const std::filesystem::path& path,
                       std::string_view source, const fileio::FileSource& files, const MeshOptions& options) {
  if (!(options.scale > 0)) throw std::invalid_argument("scale must be > 0");
  if (bytes.empty()) throw MeshError(source, "empty file: nothing to import");
  std::vector<std::string> sidecar_warnings;
  const SidecarFiles sidecars(files, path.parent_path(), std::string(source), sidecar_warnings);
  // 1. Read.
  MeshImport m;
  if (format == "gltf") {
    m = read_gltf(std::move(bytes), source, sidecars, options);
  } else if (format == "obj" || format == "fbx" || format == "dae" || format == "3ds" || format == "ply") {
    m = read_assimp(bytes, source, format, sidecars, options);
  } else {
    throw std::invalid_argument("unknown mesh format '" + std::string(format) + "'");
  }
  m.warnings.insert(m.warnings.begin(), sidecar_warnings.begin(), sidecar_warnings.end());
  // 2. Check.
  finish_geometry(m, source);
  if (m.geometry.empty()) throw MeshError(source, "the file has no triangles to import");
  // 3. Frame.
  if (options.up != MeshUp::kAuto) m.facts.up = options.up == MeshUp::kZ ? 'z' : 'y';
  to_sylva_frame(m.geometry, m.facts, options);
  const std::vector<std::string> problems = tree::validate_source_geometry(m.geometry, 1);
  if (!problems.empty()) throw MeshError(source, problems.front());
  return m;
}

}  // namespace sylva::import
