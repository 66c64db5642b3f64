// bench_hierarchy: reconstruction time of a synthetic 99.5k-triangle tree without names, as
// ez-tree writes one (every branch an open tube in one primitive; leaf quads in another): a
// 100-ring trunk, 40 laterals of 40 rings, 8 twigs of 10 rings on each, 20 leaf quads per twig.
// Run: out/build/stages/hierarchy/bench_hierarchy. Counters: triangles, and what was found.
#include <benchmark/benchmark.h>

#include <cmath>

#include "stages/hierarchy/reconstruct.h"
#include "stages/hierarchy/tests/test_meshes.h"

namespace {

using sylva::tree::Vec3;
namespace t = sylva::hierarchy::testing;

sylva::tree::Tree synthetic_tree() {
  sylva::tree::SourcePrimitive bark, leaves;
  bark.name = "tree/bark";
  leaves.name = "tree/leaves";
  leaves.material = 1;
  t::add_straight_tube(bark, {0, 0, 0}, {0, 1, 0}, 12.0, 0.4, 0.08, 100, 16);
  for (int i = 0; i < 40; ++i) {
    const double y = 3.0 + 8.0 * i / 40, a = 2.4 * i;
    const Vec3 base{0, y, 0}, dir = normalized(Vec3{std::cos(a), 0.5, std::sin(a)});
    t::add_straight_tube(bark, base, dir, 3.0, 0.08, 0.02, 40, 12);
    for (int j = 0; j < 8; ++j) {
      const Vec3 at = base + dir * (0.8 + 0.25 * j);
      const double b = a + (j % 2 ? 0.9 : -0.9);
      const Vec3 tdir = normalized(Vec3{std::cos(b), 0.7, std::sin(b)});
      t::add_straight_tube(bark, at, tdir, 0.6, 0.015, 0.006, 10, 8);
      for (int k = 0; k < 20; ++k) {
        const Vec3 petiole = at + tdir * (0.05 + 0.027 * k);
        t::add_quad(leaves, petiole, normalized(Vec3{0, 1, 0.3 * (k % 3 - 1)}), {1, 0, 0}, 0.08, 0.04);
      }
    }
  }
  sylva::tree::Tree tree;
  tree.source.primitives = {bark, leaves};
  tree.source.materials = t::materials();
  return tree;
}

void BM_Reconstruct(benchmark::State& state) {
  const sylva::tree::Tree tree = synthetic_tree();
  std::size_t triangles = 0;
  for (const auto& p : tree.source.primitives) triangles += p.indices.size() / 3;
  sylva::hierarchy::Reconstruction r;
  for (auto _ : state) {
    r = sylva::hierarchy::reconstruct(tree, {});
    benchmark::DoNotOptimize(r);
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["branches"] = static_cast<double>(r.tree.branches.size());  // 361 expected
  state.counters["leaves"] = static_cast<double>(r.tree.leaves.size());      // 6400 expected
  state.counters["left_out"] = static_cast<double>(r.report.left_out.size());
}
BENCHMARK(BM_Reconstruct)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
