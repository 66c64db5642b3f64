#include "libs/gltf/optimize.h"

#include <meshoptimizer.h>

#include <vector>

namespace sylva::gltf {

namespace {

// Every per-vertex array remapped: new vertex remap[v] takes old vertex v (~0u: dropped).
void remap_vertices(Primitive& p, const std::vector<unsigned int>& remap, std::size_t new_count) {
  const std::size_t n = p.vertex_count();
  auto apply = [&](std::vector<float>& values, std::size_t components) {
    if (values.empty()) return;
    std::vector<float> out(new_count * components);
    meshopt_remapVertexBuffer(out.data(), values.data(), n, components * sizeof(float), remap.data());
    values = std::move(out);
  };
  apply(p.positions, 3);
  apply(p.normals, 3);
  apply(p.tangents, 4);
  apply(p.texcoords, 2);
  apply(p.colors, 4);
  for (auto& c : p.custom) apply(c.values, std::size_t(c.components));
  meshopt_remapIndexBuffer(p.indices.data(), p.indices.data(), p.indices.size(), remap.data());
}

}  // namespace

void optimize_primitive(Primitive& p, OptimizeOrder order) {
  if (p.indices.empty() || p.mode == PrimitiveMode::kPoints) return;
  const std::size_t n = p.vertex_count();
  if (p.mode == PrimitiveMode::kTriangles && p.indices.size() % 3 == 0) {
    if (order == OptimizeOrder::kSize) {
      // In place is allowed (meshoptimizer copies the input when destination == indices).
      meshopt_optimizeVertexCacheStrip(p.indices.data(), p.indices.data(), p.indices.size(), n);
    } else {
      std::vector<unsigned int> tmp(p.indices.size());
      meshopt_optimizeVertexCache(tmp.data(), p.indices.data(), p.indices.size(), n);
      meshopt_optimizeOverdraw(p.indices.data(), tmp.data(), tmp.size(), p.positions.data(), n,
                               3 * sizeof(float), 1.05f);
    }
  }
  if (p.mode == PrimitiveMode::kLines && order == OptimizeOrder::kSize) return;  // (optimize.h)
  std::vector<unsigned int> remap(n);
  const std::size_t used =
      meshopt_optimizeVertexFetchRemap(remap.data(), p.indices.data(), p.indices.size(), n);
  remap_vertices(p, remap, used);
}

void optimize_scene(Scene& s, OptimizeOrder order) {
  for (auto& m : s.meshes)
    for (auto& p : m.primitives) optimize_primitive(p, order);
}

}  // namespace sylva::gltf
