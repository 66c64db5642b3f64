// The final bark surface for glTF: smooth vertex normals, texture seams and triangles.
//
// Seed: Nystad 2010 §3.3.1 (vertex attributes: position, normal, tangent, texture coordinates).
// No tangents: glTF needs them only with a normal map, and the bark has none (the lead's rule:
// a writer emits tangents only for a material with a normal map, and stages do not compute
// them); a client that wants them derives MikkTSpace tangents, as the glTF spec says.
//
//   - Normals: per topological vertex, the normalised sum of its quads' (area-weighted) normals,
//     so the surface is smooth across texture seams.
//   - Seams: glTF has one uv per vertex; a vertex whose quads give it different uvs becomes one
//     glTF vertex per distinct uv (first use order), sharing position and normal.
//   - Triangles: each quad is split along its shorter diagonal (ties: corner 0 to 2), keeping
//     the quad's counter-clockwise order.
#pragma once

#include "libs/gltf/scene.h"
#include "stages/mesh/quad_mesh.h"

namespace sylva::mesh {

// A TRIANGLES primitive with positions, normals, texcoords and indices (material -1).
gltf::Primitive to_primitive(const QuadMesh& mesh);

}  // namespace sylva::mesh
