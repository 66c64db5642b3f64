// Test helper: compares triangle index lists as meshoptimizer's index codec leaves them (the
// same triangles, each possibly rotated to start at another corner). Linked only by tests
// (sylva_gltf_testing).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>

namespace sylva::gltf::testing {

// The index triples of `bytes` (little-endian indices of `stride` bytes, 1 to 4), each rotated to
// start at its smallest index, as a multiset; a trailing incomplete triple is left out.
std::multiset<std::array<std::uint32_t, 3>> rotated_triangles(const std::string& bytes, std::size_t stride);

}  // namespace sylva::gltf::testing
