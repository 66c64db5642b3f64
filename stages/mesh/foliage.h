// Foliage geometry: leaf cards and needles, as glTF primitives separate from the bark.
//
// Seeds: Nystad 2010 §5.5.4 (a leaf is a quad from position, direction, orientation, length,
// width and a "type" choosing one cell of the leaf texture); libs/tree/foliage.h (atlas_cell():
// the atlas layout, v from the petiole or twig base (low) to the tip).
//
//   - Leaf quad (a leaf, or a twig or shoot card): 4 vertices, 2 triangles, counter-clockwise
//     seen from the leaf's normal side; normal = the leaf normal; u across the width (u0 on the
//     -side edge, side = cross(normal, direction)), v base -> tip, inside the variant's atlas
//     cell. No tangents (no normal map). Meant for an alpha-masked, double-sided material.
//   - Needle: a thin closed tetrahedron — a triangle of the needle's radius around its base and
//     the tip — 4 vertices, 4 triangles; normals radial at the base, along the needle at the tip.
#pragma once

#include "libs/gltf/scene.h"
#include "libs/tree/tree.h"

namespace sylva::mesh {

// All leaves of the tree as one TRIANGLES primitive (positions, normals, texcoords, indices); no
// vertices when the tree has no leaves.
gltf::Primitive leaf_cards(const tree::Tree& tree);

// All needles as one TRIANGLES primitive (positions, normals, indices); no vertices when the
// tree has no needles.
gltf::Primitive needle_geometry(const tree::Tree& tree);

}  // namespace sylva::mesh
