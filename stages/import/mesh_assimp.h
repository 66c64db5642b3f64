// FBX, OBJ (+ .mtl), 3DS, PLY and Collada (.dae) -> SourceGeometry, through Assimp (Debian's
// libassimp 5.2). Reads from memory; the files beside the model (an .obj's .mtl, external
// textures) through SidecarFiles (mesh_sidecar.h).
//
// Assimp's steps: ValidateDataStructure on read; then Triangulate (quads and n-gons, counted
// in a warning), JoinIdenticalVertices (welds corners equal in every attribute: OBJ and FBX store
// a vertex per face corner, and the hierarchy stage finds parts by shared vertices), SortByPType
// (points and lines apart, then skipped with a warning) and FlipUVs (uvs in glTF's convention,
// origin at the image's top-left). Normals are taken when the file has them and left empty when
// it has none (the hierarchy and mesh stages compute what they need; inventing smooth normals
// here would hide that the file had none).
//
// Frame: the node transforms from the root (or from options.node's node, with its ancestors'
// transforms) applied. FBX: the unit from its UnitScaleFactor (centimetres per file unit) and, for
// up axis auto, its UpAxis (Z when 2, else Y). Collada and 3DS: Assimp already converts their
// unit and Z-up axes; OBJ and PLY carry neither: metres and Y up unless `scale`/`up` say otherwise.
//
// Materials: base colour (glTF-style base colour, else diffuse) with opacity as alpha, two-sided;
// opacity below 1 -> blend; an opacity texture, or a base colour texture that is a PNG with an
// alpha channel -> mask at 0.5. Textures: embedded ones copied, external ones read beside the
// model; one that is missing or neither PNG nor JPEG: a warning naming it and the material,
// which keeps its colour.
// Refused (MeshError "<source>: error: <Assimp's message>"): whatever Assimp refuses (an OBJ face
// index out of range, a truncated binary file), a PLY header whose element counts the file cannot
// hold, more geometry than options' limits.
#pragma once

#include <string>
#include <string_view>

#include "stages/import/mesh_options.h"
#include "stages/import/mesh_sidecar.h"

namespace sylva::import {

// `format`: "fbx", "obj", "3ds", "ply" or "dae" (chooses Assimp's reader by the file name it is
// given). The geometry in the file's frame; facts.unit_scale and facts.up say its unit and axis.
MeshImport read_assimp(const std::string& bytes, std::string_view source, std::string_view format,
                       const SidecarFiles& files, const MeshOptions& options);

}  // namespace sylva::import
