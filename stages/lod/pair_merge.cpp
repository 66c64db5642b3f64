// Cuts of the binary forest recorded by pair merging.
// Seed: Remolar et al. (FSA/VDF), §4 (binary forest, uniform extraction of a level of detail).
#include "stages/lod/pair_merge.h"

namespace sylva::lod {

std::size_t BinaryForest::roots() const {
  std::size_t r = 0;
  for (std::int32_t p : parent) r += p < 0 ? 1 : 0;
  return r;
}

std::vector<std::uint32_t> BinaryForest::cut_by_merges(std::size_t merges) const {
  const std::size_t limit = original + std::min(merges, size() - original);
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < limit; ++i) {
    const std::int32_t p = parent[i];
    if (p < 0 || static_cast<std::size_t>(p) >= limit) out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

std::vector<std::uint32_t> BinaryForest::cut_by_count(std::size_t count) const {
  const std::size_t merges = count >= original ? 0 : original - count;
  return cut_by_merges(merges);
}

std::vector<std::uint32_t> BinaryForest::cut_by_error(double max_error) const {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < size(); ++i) {
    if (error[i] > max_error) continue;
    const std::int32_t p = parent[i];
    if (p < 0 || error[static_cast<std::size_t>(p)] > max_error) out.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

}  // namespace sylva::lod
