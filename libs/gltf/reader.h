// Reading a glTF file back into a gltf::Scene (scene.h): what stage `pack` does with the lod
// stage's .gltf files before writing its GLBs. Reads what sylva's writer writes and the common
// core subset around it; anything else is refused with a message rather than guessed.
//
// Read: .glb and .gltf (embedded data URIs or files beside it, resolved against the file's
// directory); meshes with POSITION, NORMAL, TANGENT, TEXCOORD_0, COLOR_0 (VEC3 gets alpha 1;
// normalised integer colours are converted) and '_'-prefixed custom attributes, all FLOAT except
// COLOR_0; indices of any unsigned type; POINTS, LINES and TRIANGLES; materials (base colour
// factor and texture, normal texture, metallic, roughness, alpha mode and cutoff, double-sided,
// KHR_materials_unlit, extras); images as their encoded bytes (never decoded); texture wraps;
// nodes with translation/rotation/scale, children, extensions (e.g. MSFT_lod, written back as they
// are) and extras; asset.extras; extensionsRequired.
// Refused (ReadError): sparse accessors, non-float positions/normals (KHR_mesh_quantization),
// Draco or meshopt compressed data, node matrices, strips and fans, multiple scenes.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "libs/fileio/file_source.h"
#include "libs/gltf/scene.h"

namespace sylva::gltf {

// what(): "<file>: <element>: <problem>".
class ReadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads `path` (.glb by its extension, else .gltf) and the files it names from `files`: the disk,
// or a stage's declared inputs. Throws ReadError.
Scene read_scene(const std::filesystem::path& path, const fileio::FileSource& files = fileio::disk_files());

}  // namespace sylva::gltf
