// Triangles up to rotation (rotated_triangles.h): the index codec may start a triangle at any of
// its corners, so a decoded view is compared as a multiset of canonically rotated triples.
#include "libs/gltf/testing/rotated_triangles.h"

#include <cstring>
#include <vector>

namespace sylva::gltf::testing {

std::multiset<std::array<std::uint32_t, 3>> rotated_triangles(const std::string& bytes, std::size_t stride) {
  std::vector<std::uint32_t> idx(bytes.size() / stride);
  for (std::size_t i = 0; i < idx.size(); ++i) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + i * stride, stride);
    idx[i] = v;
  }
  std::multiset<std::array<std::uint32_t, 3>> out;
  for (std::size_t k = 0; k + 2 < idx.size(); k += 3) {
    const std::size_t r =
        idx[k] <= idx[k + 1] && idx[k] <= idx[k + 2] ? 0 : (idx[k + 1] <= idx[k + 2] ? 1 : 2);
    out.insert({idx[k + r], idx[k + (r + 1) % 3], idx[k + (r + 2) % 3]});
  }
  return out;
}

}  // namespace sylva::gltf::testing
