// Parts of an imported tree mesh: the connected pieces of each source primitive (Celba 2007,
// seed 000 §4.2.4, Algorithm 1: equivalence classes over shared vertices), after welding
// vertices whose positions lie within a tolerance, so a file that duplicates vertices along
// seams (per-face normals, texture seams) or whose tubes touch without sharing indices still
// yields one part per piece.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "libs/tree/source_geometry.h"
#include "libs/tree/vec3.h"

namespace sylva::hierarchy {

// One connected piece of one primitive. Vertices are the welded ones, numbered locally.
struct Part {
  std::uint32_t primitive = 0;                          // index into SourceGeometry::primitives
  std::vector<tree::Vec3> points;                       // m, one per welded vertex (its first source vertex)
  std::vector<float> min_v;                             // lowest texture v of the source vertices welded into
                                                        // each point; empty when the primitive has no uvs
  std::vector<std::array<std::uint32_t, 3>> triangles;  // local point indices
  std::vector<std::uint32_t> face_count;                // triangles using each point
  tree::Vec3 box_min, box_max;                          // AABB of points (m)
};

// Welds each primitive's vertices (positions within `weld_tolerance` m of an earlier vertex
// become that vertex; 0 = only shared indices connect, Celba's rule), then splits it into
// connected parts by union-find over the triangles' welded vertices. Degenerate triangles
// (two welded corners equal) are dropped. Order: by primitive, then by each part's first
// triangle; deterministic. Expects valid geometry (indices < positions.size(), a multiple of 3);
// throws HierarchyError naming the primitive otherwise. Cost: O(n) expected over vertices.
std::vector<Part> split_parts(const tree::SourceGeometry& g, double weld_tolerance);

}  // namespace sylva::hierarchy
