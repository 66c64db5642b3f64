// glTF 2.0 (.gltf and .glb) -> SourceGeometry, through tinygltf and the glTF helpers of
// libs/render's scene layer (accessors, Draco, meshopt, texture transforms). Pure but for the
// sidecar files, which are read through a SidecarFiles (mesh_sidecar.h).
//
// What is read:
//   - the default scene (else scene 0, else every node no other node lists as a child), its whole
//     node tree with matrix or TRS transforms applied (normals by the inverse transpose; a
//     mirroring transform flips the winding back to counter-clockwise);
//   - options.node: the subtree of the first node of that name, with the transforms of its
//     ancestors up to its scene root; a name no node has is a MeshError listing the named nodes;
//   - a scene root that another node lists as its child (Kenney's "tmpParent"): imported as a
//     root, without that parent's transform (glTF's rule: scene nodes are roots), with a warning
//     naming both nodes;
//   - several top-level nodes with geometry: imported together as one model, with a warning
//     naming them (set `node` to import one);
//   - primitives: TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN (expanded to lists); POINTS and LINES*
//     are skipped with a warning; POSITION, NORMAL, and the TEXCOORD_n the material's base colour
//     texture reads (TEXCOORD_0 without a texture) with KHR_texture_transform applied;
//     KHR_mesh_quantization (integer and normalised attributes), KHR_draco_mesh_compression,
//     EXT_meshopt_compression, sparse accessors;
//   - materials: base colour factor and texture, alpha mode and cutoff, double-sided, metallic and
//     roughness factors; a primitive without a material gets a white "default" material appended;
//   - images: only those a material's base colour texture uses, each once, as their PNG or JPEG
//     bytes (embedded in a buffer view or data URI, or a file beside the model). A missing image
//     file or another encoding: a warning naming the image and the material, which keeps its
//     colour and loses the texture.
// Refused (MeshError "<source>: error: ..."): invalid JSON or GLB, an extension in
// extensionsRequired that is not listed above, out-of-range indices or accessors, undecodable
// Draco or meshopt data, more geometry than options' limits, a node reached twice (glTF's nodes
// form trees: "node 3 is reached twice"), a node hierarchy deeper than 1000 levels, an accessor
// count past the limits before anything is allocated for it.
#pragma once

#include <string>
#include <string_view>

#include "stages/import/mesh_options.h"
#include "stages/import/mesh_sidecar.h"

namespace sylva::import {

// The geometry in the file's frame (glTF: metres, Y up), facts.format "gltf", unit "m", up 'y'.
// `source` names the file in messages; sidecars resolve against files.base_dir().
MeshImport read_gltf(std::string bytes, std::string_view source, const SidecarFiles& files,
                     const MeshOptions& options);

}  // namespace sylva::import
