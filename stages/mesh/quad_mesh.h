// The quad mesh the stage builds and subdivides: shared vertex positions, quads listed
// counter-clockwise seen from outside, and face-varying texture coordinates (one uv per face
// corner, so a texture seam is simply two different uvs at one vertex).
//
// Seed: Nystad 2010 §5.3.2 (quads from mesh points), §3.4 (texture coordinates per vertex; we keep
// them per face corner so the glTF seam needs no special case until export).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "libs/tree/vec3.h"

namespace sylva::mesh {

using tree::Vec3;

// Texture coordinates in float, as glTF stores them (half the memory of double on meshes of
// millions of quads; exact for the ring u values).
struct Uv {
  float u = 0, v = 0;
  friend bool operator==(const Uv&, const Uv&) = default;
};

using Quad = std::array<std::uint32_t, 4>;

// Where a quad comes from (box_joints.h); kept through subdivision, used by statistics and tests.
enum class FaceKind : std::uint8_t {
  kTube,    // between two rings of one branch
  kJoint,   // between a port and a child's first ring
  kCap,     // a tip or base cap
  kRim,     // around an inset port
  kCrotch,  // the ridge of an equal split
  kBox,     // a backward box
};

struct QuadMesh {
  std::vector<Vec3> positions;  // m, object space
  // Vertex indices, CCW seen from outside. A triangle (only in the transition between smooth and
  // flat regions of subdivide_selected) is a quad whose last two corners are equal.
  std::vector<Quad> quads;
  std::vector<std::array<Uv, 4>> uvs;  // per quad corner; same size as quads
  std::vector<FaceKind> kinds;         // per quad; same size as quads
  // Per vertex, 1 = on a crease curve (empty = none): an edge between two crease vertices is an
  // infinitely sharp crease for Catmull–Clark (subdivision.h). The capped base ring of a trunk.
  std::vector<std::uint8_t> crease;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t quad_count() const { return quads.size(); }
};

}  // namespace sylva::mesh
