// The full-detail model of a lod node (full_detail.h), through the lod stage's chain.
#include "app/full_detail.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "libs/tree/sylt_format.h"
#include "stages/lod/chain.h"
#include "stages/lod/lod_gltf.h"
#include "stages/lod/lod_stage.h"

namespace sylva {

namespace {

std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw std::runtime_error(p.string() + ": cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

std::string lod_full_detail_glb(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& lod_node,
                                bool branches_only) {
  const InputArtifact tree_in = input_artifact(recipe, built, lod_node.needs.at(0));
  const ArtifactFile* sylt = tree_in.file("tree.sylt");
  if (!sylt) throw std::runtime_error("input '" + tree_in.node + "' has no tree.sylt");
  const tree::Tree tree = tree::read_sylt(sylt->path);
  const lod::ChainOptions chain = chain_options_from_params(lod_node.params);
  lod::OutputTextures tex;
  if (!tree.materials.leaf_texture.empty())
    if (const ArtifactFile* f = tree_in.file(tree.materials.leaf_texture)) tex.leaf_png = read_bytes(f->path);
  const lod::Precomputed pre = lod::precompute(tree, chain);
  return lod::encode_full_detail(tree, lod::build_full_detail(tree, pre, chain), tex, branches_only);
}

}  // namespace sylva
