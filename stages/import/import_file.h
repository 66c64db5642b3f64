// Bytes of one file -> tree: format detection and dispatch to the parsers. Pure (no I/O) but
// for a mesh's sidecar files (a .gltf's buffers, an .obj's .mtl, textures), read through
// ImportOptions::files; the stage adapter (import_stage.cpp) reads the file and writes the result.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "libs/fileio/file_source.h"
#include "libs/tree/tree.h"
#include "stages/import/mesh_options.h"
#include "stages/import/qsm_to_tree.h"

namespace sylva::import {

enum class Format {
  kQsm,           // QSM cylinder table with a header line (CSV, TSV, ...)
  kTreeQsmText,   // headerless TreeQSM cylinder text (column order: TableOptions::columns)
  kSkeletonText,  // sylva text skeleton (skeleton_text.h)
  kSylt,          // native .sylt (libs/tree/sylt_format.h)
  // Tree meshes (mesh_import.h): the geometry goes to Tree::source, the skeleton stays empty
  // (stage `hierarchy` reconstructs it).
  kGltf,  // glTF 2.0, .gltf (JSON) or .glb
  kObj,   // Wavefront OBJ (+ .mtl)
  kFbx,   // Autodesk FBX, binary or ASCII
  kDae,   // Collada
  k3ds,   // 3D Studio
  kPly,   // Stanford PLY with faces
};

// True for the mesh formats (kGltf and after).
bool is_mesh_format(Format f);

// The `format` parameter's spelling: "qsm", "treeqsm_txt", "skeleton_txt", "sylt", "gltf", "obj",
// "fbx", "dae", "3ds", "ply".
const char* format_name(Format f);

// Resolves format "auto" from the bytes and the file name, first rule that matches:
//   1. the bytes start with the .sylt magic, or the name ends in ".sylt"  -> sylt;
//   1a. the bytes start with the GLB magic "glTF", or are a JSON object with an "asset" member
//       in their first 4 KiB, or the name ends in ".gltf" or ".glb"    -> gltf;
//   1b. the bytes start with "ply" and the header declares faces     -> ply (a PLY without faces
//       is a point cloud: refused with that answer, as LAS and the rest);
//   1c. the name ends in ".obj", ".fbx", ".dae", ".3ds", or the bytes start with
//       "Kaydara FBX Binary"                                          -> obj, fbx, dae, 3ds;
//   2. the name ends in ".skel"                                         -> skeleton_txt;
//   3. `has_columns` (the columns parameter is set)                     -> treeqsm_txt;
//   4. the first line that is not blank or a '#' comment:
//        has a field that is not a number (a header)                    -> qsm;
//        12 or more numeric fields                                      -> treeqsm_txt;
//        6 to 9 numeric fields                                          -> skeleton_txt.
// Throws ImportError for an empty file or a first line that fits none of these.
Format detect_format(std::string_view bytes, std::string_view file_name, bool has_columns,
                     std::string_view source);

struct ImportOptions {
  std::string format = "auto";       // "auto" or a format_name()
  std::vector<std::string> columns;  // headerless column names (treeqsm_txt)
  QsmToTreeOptions qsm;              // frame/unit conversion; QSM formats only
  MeshOptions mesh;                  // frame/unit conversion and node; mesh formats only
  // Where a mesh's sidecar files are read (nullptr: the disk); must outlive the call.
  const fileio::FileSource* files = nullptr;
};

// A tree and what its import said: warnings (mesh formats; "<source>: warning: ..."), and for a
// mesh the facts of its conversion.
struct ImportResult {
  tree::Tree tree;
  Format format = Format::kQsm;
  std::vector<std::string> warnings;
  MeshFacts mesh;  // mesh formats only
};

// The tree in `bytes`. `source` names the file in messages (and its extension feeds auto
// detection). Throws ImportError (text formats: "<source>:<line>: ...") or
// tree::TreeFormatError (.sylt: "<source>: byte <n>: ..."); std::invalid_argument for options
// that contradict each other (columns with format qsm). The result passes validate_tree.
// A mesh format's tree is named "<format> mesh, <n> triangles" and has no branches; its
// geometry is in `source`. Mesh formats throw MeshError ("<source>: error: ...").
tree::Tree import_tree(std::string_view bytes, std::string_view source, const ImportOptions& options);
// The same with the warnings and facts.
ImportResult import_file(std::string_view bytes, std::string_view source, const ImportOptions& options);

}  // namespace sylva::import
