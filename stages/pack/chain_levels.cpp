// The pack reads the chain only through libs/lodchain, which owns the MSFT_lod metadata, so the
// lod stage and the pack agree on what a level's node says.
#include "stages/pack/chain_levels.h"

#include "libs/lodchain/chain_gltf.h"
#include "libs/lodmodel/lod_model.h"

namespace sylva::pack {

void count_primitives(const gltf::Scene& s, LodLevel& l) {
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) {
      const std::size_t n = p.indices.empty() ? p.vertex_count() : p.indices.size();
      if (p.mode == gltf::PrimitiveMode::kTriangles) l.triangles += n / 3;
      if (p.mode == gltf::PrimitiveMode::kLines) l.lines += n / 2;
    }
}

// The chain's MSFT_lod links and every level's numbers (lodchain::read_chain_levels).
ParsedChain parse_chain(const SpeciesInput& in) {
  const gltf::Scene& chain = in.chain;
  const std::vector<lodchain::ChainLevelNumbers> levels =
      lodchain::read_chain_levels(chain.roots, chain.nodes.size(), in.levels.size(), [&](std::size_t n) {
        return lodchain::ChainNode{&chain.nodes[n].extras, &chain.nodes[n].extensions};
      });
  ParsedChain out;
  for (const lodchain::ChainLevelNumbers& n : levels) {
    ChainLevel l;
    l.node = &chain.nodes[std::size_t(n.node)];
    l.epsilon_m = n.epsilon_m;
    l.pixel_error_px = n.pixel_error_px;
    l.switch_distance_m = n.switch_distance_m;
    l.coverage = n.screen_coverage;
    out.coverage.push_back(l.coverage);
    out.levels.push_back(l);
  }
  return out;
}

std::uint64_t primitives_of(const gltf::Scene& s) {
  LodLevel l;
  count_primitives(s, l);
  std::uint64_t points = 0;
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives)
      if (p.mode == gltf::PrimitiveMode::kPoints)
        points += p.indices.empty() ? p.vertex_count() : p.indices.size();
  return l.triangles + l.lines + points;
}

double bounding_radius(const gltf::Scene& s) {
  lodmodel::BoundingBox box;
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) box.extend(p.positions);
  return box.radius();
}

}  // namespace sylva::pack
