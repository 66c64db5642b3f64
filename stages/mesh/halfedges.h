// Private to stages/mesh: half-edge adjacency of a quad mesh. Half-edge h = 4 * quad + corner
// runs from corner h % 4 to corner (h + 1) % 4 of quad h / 4.
#pragma once

#include <cstdint>
#include <vector>

#include "stages/mesh/quad_mesh.h"

namespace sylva::mesh::detail {

inline constexpr std::uint32_t kNoHalfedge = 0xFFFFFFFFu;

// The opposite of every half-edge (the half-edge b -> a of another quad for a -> b), or
// kNoHalfedge on a boundary. Where an edge has more than two quads (not a manifold) the first
// match in (quad, corner) order is taken. O(quads * valence).
std::vector<std::uint32_t> opposite_halfedges(const QuadMesh& mesh);

}  // namespace sylva::mesh::detail
