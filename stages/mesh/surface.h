// The final bark surface for glTF: smooth vertex normals, tangents, texture seams and triangles.
//
// Seed: Nystad 2010 §3.3.1 (vertex attributes: position, normal, tangent, texture coordinates).
//
//   - Normals: per topological vertex, the normalised sum of its quads' (area-weighted) normals,
//     so the surface is smooth across texture seams.
//   - Seams: glTF has one uv per vertex; a vertex whose quads give it different uvs becomes one
//     glTF vertex per distinct uv (first use order), sharing position and normal.
//   - Tangents: per glTF vertex, the sum of its triangles' dP/du, each weighted by the
//     triangle's uv area, made orthogonal to the normal; w = the sign of the summed uv area
//     (+1: the uv frame is right-handed about the outward normal, so normal x tangent points
//     along dP/dv). Where dP/du vanishes (degenerate uvs) any unit vector orthogonal to the
//     normal is used.
//   - Triangles: each quad is split along its shorter diagonal (ties: corner 0 to 2), keeping
//     the quad's counter-clockwise order.
#pragma once

#include "libs/gltf/scene.h"
#include "stages/mesh/quad_mesh.h"

namespace sylva::mesh {

// A TRIANGLES primitive with positions, normals, tangents, texcoords and indices (material -1).
gltf::Primitive to_primitive(const QuadMesh& mesh);

}  // namespace sylva::mesh
