// The forest's ground mesh (ground.h).
#include "stages/forest/ground.h"

#include <algorithm>
#include <cmath>

namespace sylva::forest {

gltf::Scene ground_scene(const Terrain& terrain, const std::array<double, 2>& lo,
                         const std::array<double, 2>& hi) {
  const double w = hi[0] - lo[0], d = hi[1] - lo[1];
  int nx = 1, nz = 1;
  double ex = w, ez = d;  // central-difference steps
  if (!terrain.empty()) {
    const Field& f = terrain.field;
    const double sx = (f.x1 - f.x0) / std::max(1, f.cols - 1), sz = (f.z1 - f.z0) / std::max(1, f.rows - 1);
    nx = std::clamp(int(std::ceil(w / sx - 1e-9)), 1, kMaxGroundCells);
    nz = std::clamp(int(std::ceil(d / sz - 1e-9)), 1, kMaxGroundCells);
    ex = sx;
    ez = sz;
  }
  gltf::Primitive p;
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = lo[0] + w * i / nx, z = lo[1] + d * j / nz;
      double y = 0, gx = 0, gz = 0;
      if (!terrain.empty()) {
        y = terrain.height(x, z);
        gx = (terrain.height(x + ex, z) - terrain.height(x - ex, z)) / (2 * ex);
        gz = (terrain.height(x, z + ez) - terrain.height(x, z - ez)) / (2 * ez);
      }
      const double len = std::sqrt(gx * gx + 1 + gz * gz);
      p.positions.insert(p.positions.end(), {float(x), float(y), float(z)});
      p.normals.insert(p.normals.end(), {float(-gx / len), float(1 / len), float(-gz / len)});
    }
  // Counter-clockwise seen from +Y: (x, z), (x, z + 1), (x + 1, z) and so on.
  for (int j = 0; j < nz; ++j)
    for (int i = 0; i < nx; ++i) {
      const auto v = [&](int a, int b) { return std::uint32_t((j + b) * (nx + 1) + i + a); };
      p.indices.insert(p.indices.end(), {v(0, 0), v(0, 1), v(1, 0), v(1, 0), v(0, 1), v(1, 1)});
    }
  p.material = 0;
  gltf::Scene s;
  gltf::Material m;
  m.name = "ground";
  m.base_color = kGroundColor;
  m.roughness = 1;
  s.materials.push_back(m);
  gltf::Mesh mesh;
  mesh.name = "ground";
  mesh.primitives.push_back(std::move(p));
  s.meshes.push_back(std::move(mesh));
  gltf::Node n;
  n.name = "ground";
  n.mesh = 0;
  s.nodes.push_back(std::move(n));
  s.roots = {0};
  return s;
}

}  // namespace sylva::forest
