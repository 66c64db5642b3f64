// Foliage simplification by leaf collapse (FSA) and its binary forest (VDF).
//
// Seed: Remolar et al., "View-dependent multiresolution model for foliage" (FSA/VDF), §3 (leaf
// collapse: the pair with the lowest cost, combining distance and planarity, becomes one leaf
// whose four vertices are two vertices of each collapsed leaf, so no vertex is created and the
// area stays close to the pair's) and §4 (binary forest; uniform extraction).
//
// Our cost (the paper names its terms, not its weights; docs/stages/lod.md):
//   cost(a, b) = |c_a - c_b| + 0.5 (sqrt(A_a) + sqrt(A_b)) (1 - |n_a . n_b|)      [m]
// the distance of the centroids plus the planarity term: how far a leaf of the pair's size
// tilts out of the other's plane. The error of a collapsed leaf is
//   err(z) = max(err(a), err(b)) + cost(a, b),
// monotone towards the roots, so cut_by_error() gives a consistent level for a spatial error.
// Vertex placement: of the 4 x 4 edge pairs (and both orders), the quad whose area is closest to
// A_a + A_b (ties: lowest index); the vertices keep their texture coordinates.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "libs/tree/tree.h"
#include "stages/lod/pair_merge.h"

namespace sylva::lod {

struct LeafQuad {
  std::array<tree::Vec3, 4> v;             // corners, counter-clockwise seen from the front
  std::array<std::array<float, 2>, 4> uv;  // texture coordinates of the corners (leaf atlas)
  tree::Vec3 normal;                       // unit front normal
  double area = 0;                         // m^2 (half |d1 x d2|)
  tree::Vec3 center() const { return (v[0] + v[1] + v[2] + v[3]) * 0.25; }
};

// Corners of a tree leaf quad — a leaf, or a twig or shoot card (tree.h: from the petiole or
// card base along `direction`, `width` across cross(normal, direction)) with the uv of its
// variant's atlas cell (libs/tree/foliage.h atlas_cell(); default materials: the 2x2 atlas).
// A card is FSA's four-vertex unit like a leaf, so the collapse below reduces cards unchanged.
LeafQuad leaf_quad(const tree::Leaf& leaf, const tree::Materials& materials = {});

double leaf_collapse_cost(const LeafQuad& a, const LeafQuad& b);

// The collapsed leaf of a and b (vertex placement above).
LeafQuad collapse_leaves(const LeafQuad& a, const LeafQuad& b);

struct LeafForest {
  std::vector<LeafQuad> quads;  // originals, then one per collapse
  BinaryForest forest;
};

// FSA over all leaves (or cards) of a tree.
LeafForest build_leaf_forest(std::span<const tree::Leaf> leaves, const tree::Materials& materials = {});

struct LeafGeometry {
  std::vector<float> positions, normals, texcoords;  // 4 vertices per leaf
  std::vector<std::uint32_t> indices;                // 2 triangles per leaf
  std::size_t leaves = 0;
  double area = 0;  // total leaf area, m^2
};

// Appends the quads `active` (element ids of forest.quads) as geometry.
void leaf_geometry(const LeafForest& forest, std::span<const std::uint32_t> active, LeafGeometry& out);

// Appends `quads` as geometry (the card clusters' cut, card_clusters.h).
void leaf_geometry(std::span<const LeafQuad> quads, LeafGeometry& out);

}  // namespace sylva::lod
