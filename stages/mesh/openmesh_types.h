// Private to stages/mesh: the OpenMesh polygon mesh type (double precision points) and the
// conversion from QuadMesh.
#pragma once

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "stages/mesh/quad_mesh.h"

namespace sylva::mesh::detail {

struct PolyTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<PolyTraits>;

// Adds every vertex and quad in order (OpenMesh index i = QuadMesh index i). Returns the number
// of quads OpenMesh refused (a non-manifold edge or vertex, or inconsistent orientation); the
// refused quads are skipped, so face indices shift after the first refusal.
std::size_t to_openmesh(const QuadMesh& in, PolyMesh& out);

}  // namespace sylva::mesh::detail
