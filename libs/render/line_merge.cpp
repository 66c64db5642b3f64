// Merging runs of coincident lines (line_merge.h says why the composite is unchanged).
#include "libs/render/line_merge.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace sylva::render {
namespace {

template <class T>
bool same_bits(const std::vector<T>& v, std::uint32_t a, std::uint32_t b) {
  return v.empty() || std::memcmp(v[a].data(), v[b].data(), sizeof(T)) == 0;
}

}  // namespace

MergedLines merge_coincident_lines(const Primitive& p) {
  if (p.topology != Topology::kLines) throw std::invalid_argument("merge_coincident_lines: not LINES");
  if (p.indices.size() % 2 != 0) throw std::invalid_argument("merge_coincident_lines: odd index count");
  MergedLines out;
  const std::size_t n = p.indices.size() / 2;
  out.source_segments = n;
  auto vertex_equal = [&](std::uint32_t a, std::uint32_t b) {
    return same_bits(p.positions, a, b) && same_bits(p.colors, a, b) && same_bits(p.texcoords, a, b);
  };
  std::size_t s = 0;
  while (s < n) {
    const std::uint32_t a = p.indices[2 * s], b = p.indices[2 * s + 1];
    std::size_t k = 1;
    while (k < std::size_t(kMaxMergedLines) && s + k < n && vertex_equal(a, p.indices[2 * (s + k)]) &&
           vertex_equal(b, p.indices[2 * (s + k) + 1]))
      ++k;
    for (int end = 0; end < 2; ++end) {
      const std::uint32_t v = end == 0 ? a : b;
      out.positions.push_back(p.positions[v]);
      if (!p.texcoords.empty()) out.texcoords.push_back(p.texcoords[v]);
      if (!p.colors.empty()) out.colors.push_back(p.colors[v]);
      out.copies.push_back(float(k));
      if (!p.normals.empty())
        for (std::size_t j = 0; j < std::size_t(kMaxMergedLines); ++j) {
          const std::size_t c = std::min(j, k - 1);  // fewer copies: repeat the last
          out.normals[j].push_back(p.normals[p.indices[2 * (s + c) + std::size_t(end)]]);
        }
    }
    s += k;
  }
  return out;
}

void merge_line_copies(Scene& scene) {
  for (Mesh& mesh : scene.meshes)
    for (Primitive& p : mesh.primitives) {
      if (p.topology != Topology::kLines || !p.copies.empty() || p.material < 0 ||
          std::size_t(p.material) >= scene.materials.size() ||
          scene.materials[std::size_t(p.material)].alpha_mode != AlphaMode::kBlend)
        continue;
      MergedLines merged = merge_coincident_lines(p);
      if (merged.positions.size() == p.indices.size()) continue;  // nothing coincident
      Primitive q;
      q.topology = Topology::kLines;
      q.material = p.material;
      q.positions = std::move(merged.positions);
      q.texcoords = std::move(merged.texcoords);
      q.colors = std::move(merged.colors);
      q.copies = std::move(merged.copies);
      q.indices.resize(q.positions.size());
      for (std::size_t i = 0; i < q.indices.size(); ++i) q.indices[i] = std::uint32_t(i);
      p = std::move(q);
    }
}

}  // namespace sylva::render
