// An imported tree's source geometry (libs/tree/source_geometry.h) as glTF scene parts: the
// user's own model, drawn as the file had it.
//
// Contract:
//   - one glTF primitive (TRIANGLES, indexed) per SourcePrimitive, in order, positions copied
//     bit for bit; uvs copied; normals renormalised to unit length (the scene's 1e-4 tolerance is
//     stricter than the source's 1e-3) or, where the source has none, computed as the
//     area-weighted mean of the adjacent faces' normals (a vertex on no non-degenerate face gets
//     +Y);
//   - one glTF material per source material (name, base colour, alpha mode and cutoff,
//     double-sidedness, metallic, roughness; the base colour image as a REPEAT-wrapped texture);
//     images embedded byte for byte;
//   - appended: indices into an existing scene's materials and images are offset, so a scene
//     may hold other meshes (a chain's coarser levels) beside it.
// The result passes gltf::validate_scene() whenever the SourceGeometry passes
// tree::validate_source_geometry().
#pragma once

#include <string>

#include "libs/gltf/scene.h"
#include "libs/tree/source_geometry.h"

namespace sylva::sourcegltf {

// Appends `g` to `scene` as one mesh named `mesh_name` with its materials and images; returns the
// new mesh's index. Does not add a node. Throws std::invalid_argument if `g` is empty.
int append_source_mesh(gltf::Scene& scene, const tree::SourceGeometry& g, const std::string& mesh_name);

// A scene holding only `g`: one root node `node_name` drawing append_source_mesh's mesh.
gltf::Scene source_scene(const tree::SourceGeometry& g, const std::string& node_name);

// Triangles over every primitive of `g`.
std::size_t source_triangle_count(const tree::SourceGeometry& g);

}  // namespace sylva::sourcegltf
