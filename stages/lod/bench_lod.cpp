// Benchmark of the lod core (a separate executable, never a timed unit test):
//   - BM_MergeAndPolygonize: internode merging (eq. 3-5) + polygonisation (eq. 9-12) over every
//     branch of a tree at one epsilon; items/s = input internodes per second;
//   - BM_Chain/<preset>: the whole chain (precompute incl. FSA/E5 forests + every level) of every
//     adult preset with the default options (6 levels, 1 mm .. 0.22 m);
//   - BM_ChainClusters/<preset>: the same chain with card clusters (card_cluster_px 0.35);
//   - BM_LeafForest/<preset>, BM_NeedleForest/<preset>: the one-off agglomeration alone (FSA leaf
//     collapse, E5 needle merging; pair_merge.h), the part of the chain that dominated it;
//   - BM_MergeStraightChain/<nodes>: merging one straight, gently wavy branch of 5k-80k nodes at
//     E1 = E2 = 5 mm (everything merges into long groups: the case that was quadratic);
//   - BM_ChainLongBranch/30000: the whole default chain of a tree that is one such branch.
// Seeds: Zhang et al. 2017 §4–§6; Remolar et al. FSA/VDF.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "pipeline/rng.h"
#include "stages/generate/preset.h"
#include "stages/generate/weber_penn.h"
#include "stages/lod/chain.h"
#include "stages/lod/foliage.h"
#include "stages/lod/needles.h"

namespace {

using namespace sylva;

const tree::Tree& adult(const std::string& species) {
  static std::map<std::string, tree::Tree> cache;
  auto it = cache.find(species);
  if (it != cache.end()) return it->second;
  const auto sp = generate::load_species_preset(std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species" /
                                                (species + ".yaml"));
  generate::GenerateOptions o;
  o.max_node_spacing = 0.5;
  Rng rng(1, "tree");
  return cache.emplace(species, generate::generate_tree(sp.age("adult").params, o, rng)).first->second;
}

void BM_MergeAndPolygonize(benchmark::State& state, const std::string& species, double eps) {
  const tree::Tree& t = adult(species);
  const auto sk = lod::build_skeletons(t);
  std::size_t internodes = 0;
  for (const auto& b : sk) internodes += b.g.size() - 1;
  const lod::MergeLimits limits{eps / 4, eps / 4, 1.047};
  std::vector<std::uint32_t> kept;
  for (auto _ : state) {
    lod::BranchGeometry geo;
    for (const auto& b : sk) {
      kept.clear();
      lod::merge_internodes(b.g, limits, kept);
      lod::polygonize_branch(b.g, kept, eps, 12, geo);
    }
    benchmark::DoNotOptimize(geo.tri_indices.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * internodes));
  state.counters["internodes"] = static_cast<double>(internodes);
}

void BM_Chain(benchmark::State& state, const std::string& species) {
  const tree::Tree& t = adult(species);
  lod::ChainOptions o;
  for (auto _ : state) {
    auto levels = lod::build_chain(t, o);
    benchmark::DoNotOptimize(levels.data());
  }
  state.counters["leaves"] = static_cast<double>(t.leaves.size());
  state.counters["needles"] = static_cast<double>(t.needles.size());
  state.counters["branches"] = static_cast<double>(t.branches.size());
}

// The chain with card clusters on (card_cluster_px 0.35, as the default recipe's birch): the
// extra cost is the cluster forest and the overlap rasters of the coarse levels' clusters.
void BM_ChainClusters(benchmark::State& state, const std::string& species) {
  const tree::Tree& t = adult(species);
  lod::ChainOptions o;
  o.card_cluster_px = 0.35;
  for (auto _ : state) {
    auto levels = lod::build_chain(t, o);
    benchmark::DoNotOptimize(levels.data());
  }
  state.counters["leaves"] = static_cast<double>(t.leaves.size());
}

void BM_LeafForest(benchmark::State& state, const std::string& species) {
  const tree::Tree& t = adult(species);
  for (auto _ : state) {
    auto forest = lod::build_leaf_forest(t.leaves);
    benchmark::DoNotOptimize(forest.forest.error.data());
  }
  state.counters["leaves"] = static_cast<double>(t.leaves.size());
}

void BM_NeedleForest(benchmark::State& state, const std::string& species) {
  const tree::Tree& t = adult(species);
  for (auto _ : state) {
    auto forest = lod::build_needle_forest(t.needles);
    benchmark::DoNotOptimize(forest.forest.error.data());
  }
  state.counters["needles"] = static_cast<double>(t.needles.size());
}

// A tree of one branch: `n` nodes 5 cm apart along +Y with a 1 mm sine wobble (period 10 m),
// radius 5 cm.
tree::Tree wavy_branch(std::size_t n) {
  tree::Tree t;
  tree::Branch b;
  for (std::size_t i = 0; i < n; ++i) {
    const double y = 0.05 * static_cast<double>(i);
    b.nodes.push_back({{0.001 * std::sin(y * 0.628), y, 0}, 0.05});
  }
  t.branches.push_back(b);
  return t;
}

void BM_MergeStraightChain(benchmark::State& state) {
  const tree::Tree t = wavy_branch(static_cast<std::size_t>(state.range(0)));
  const std::size_t n = t.branches[0].nodes.size();
  const auto sk = lod::build_skeletons(t);
  const lod::MergeLimits limits{0.005, 0.005, 1.047};
  std::vector<std::uint32_t> kept;
  for (auto _ : state) {
    kept.clear();
    lod::merge_internodes(sk[0].g, limits, kept);
    benchmark::DoNotOptimize(kept.data());
  }
  state.counters["kept"] = static_cast<double>(kept.size());
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
}

// The whole chain (6 levels, default options) of a tree that is one such branch: merging,
// topology, polygonisation; the issue-15 case (a 30k-node chain took ~215 s before).
void BM_ChainLongBranch(benchmark::State& state) {
  const tree::Tree t = wavy_branch(static_cast<std::size_t>(state.range(0)));
  lod::ChainOptions o;
  for (auto _ : state) {
    auto levels = lod::build_chain(t, o);
    benchmark::DoNotOptimize(levels.data());
  }
}

}  // namespace

BENCHMARK(BM_ChainLongBranch)->Arg(30000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MergeStraightChain)
    ->Arg(5000)
    ->Arg(10000)
    ->Arg(20000)
    ->Arg(40000)
    ->Arg(80000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MergeAndPolygonize, oak_1mm, std::string("oak"), 0.001)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MergeAndPolygonize, oak_22cm, std::string("oak"), 0.22)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Chain, birch, std::string("birch"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Chain, holly, std::string("holly"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Chain, mugo_pine, std::string("mugo_pine"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Chain, norway_spruce, std::string("norway_spruce"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Chain, oak, std::string("oak"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Chain, scots_pine, std::string("scots_pine"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Chain, weeping_willow, std::string("weeping_willow"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Chain, white_poplar, std::string("white_poplar"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_ChainClusters, birch, std::string("birch"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ChainClusters, oak, std::string("oak"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_LeafForest, oak, std::string("oak"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_LeafForest, white_poplar, std::string("white_poplar"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_NeedleForest, scots_pine, std::string("scots_pine"))->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
