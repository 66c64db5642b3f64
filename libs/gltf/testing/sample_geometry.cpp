// The shared scene pieces of the glTF tests (sample_geometry.h).
#include "libs/gltf/testing/sample_geometry.h"

#include <cmath>
#include <cstdint>
#include <utility>

namespace sylva::gltf::testing {

Node make_node(std::string name, int mesh, std::vector<int> children) {
  Node n;
  n.name = std::move(name);
  n.mesh = mesh;
  n.children = std::move(children);
  return n;
}

Primitive wavy_grid(int n) {
  Primitive t;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = float(i) / float(n), z = float(j) / float(n);
      t.positions.insert(t.positions.end(), {x, 0.1f * std::sin(7 * x) * std::cos(5 * z), z});
      t.normals.insert(t.normals.end(), {0, 1, 0});
      t.texcoords.insert(t.texcoords.end(), {x, z});
    }
  const auto at = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      t.indices.insert(t.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      t.indices.insert(t.indices.end(), {at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  return t;
}

}  // namespace sylva::gltf::testing
