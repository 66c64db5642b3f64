// The level of an imported tree that is the imported model itself (docs/stages/lod.md
// "Imported trees"): the user's triangles are the truth every other level is judged against, so
// the finest level draws them unchanged rather than a re-meshing of the reconstructed skeleton.
#include <stdexcept>

#include "stages/lod/chain.h"

namespace sylva::lod {

Level source_level(const tree::Tree& tree, const LevelSpec& spec) {
  if (tree.source.empty())
    throw std::invalid_argument("tree '" + tree.name + "' has no source geometry to draw as a level");
  Level l;
  l.spec = spec;
  l.source = &tree.source;
  for (const tree::SourcePrimitive& p : tree.source.primitives) l.counts.triangles += p.indices.size() / 3;
  return l;
}

}  // namespace sylva::lod
