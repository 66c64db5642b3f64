// The checks every mesh reader's result goes through before it leaves the import (pure):
// limits, degenerate faces, normals, material ranges. Each fix is a warning; what cannot be
// fixed is a MeshError. The rules, for users, are in docs/stages/import.md "Warnings".
#pragma once

#include <cstddef>
#include <string_view>

#include "stages/import/mesh_options.h"

namespace sylva::import {

// Throws MeshError "<source>: error: the model has more than <max> vertices|triangles (the import's
// limit, tree::kMaxSourceVertices|Triangles)" when a count passes options' limits. The readers
// call it as they add geometry, so memory stays bounded by the limits.
void check_mesh_limits(std::string_view source, std::size_t vertices, std::size_t triangles,
                       const MeshOptions& options);

// In this order, on m.geometry:
//   - a non-finite position: MeshError naming the primitive and the vertex;
//   - normals that are not finite or of zero length: that primitive's normals dropped (warning);
//     the others normalised; non-finite texture coordinates: that primitive's uvs dropped;
//   - degenerate triangles (a vertex index repeated, or three positions on one line, exactly):
//     dropped, one warning with the count and the primitives they were in;
//   - primitives left without triangles: dropped (one warning naming them); then materials no
//     primitive uses and images no material uses (renumbered in order, silently);
//   - material base colour, metallic, roughness and alpha cutoff outside [0, 1]: clamped, a
//     warning per material naming it.
// Then fills m.facts.vertices and m.facts.triangles.
void finish_geometry(MeshImport& m, std::string_view source);

}  // namespace sylva::import
