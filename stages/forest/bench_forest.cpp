// Placement benchmarks (issue 13 "Measures"): Celba's method (Algorithm 8, grid overlap test)
// for 1,000,000 trees over 100 km^2 (10 x 10 km at 100 trees/ha, three species), and the Poisson
// method's points per second. Run: out/build/stages/forest/bench_forest
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "stages/forest/layout.h"

namespace sylva::forest {
namespace {

SpeciesRule rule(const char* name, double density, double half_width, double height) {
  SpeciesRule s;
  s.name = name;
  s.density_per_ha = density;
  s.bounds = {{-half_width, 0, -half_width}, {half_width, height, half_width}};
  s.scale_x = s.scale_z = {0.8, 1.2};
  s.scale_y = {0.8, 1.2};
  return s;
}

// FNV-1a over every placed tree's species, position, yaw and scale (the bytes of the doubles): the
// label of a run, so a change of the placement code can show it places the very same forest.
std::string digest(const LayoutResult& r) {
  std::uint64_t h = 1469598103934665603ull;
  auto add = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  for (const PlacedTree& t : r.trees) {
    add(&t.species, sizeof t.species);
    add(t.position.data(), sizeof(double) * 3);
    add(&t.yaw_rad, sizeof t.yaw_rad);
    add(t.scale.data(), sizeof(double) * 3);
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "forest %016llx", static_cast<unsigned long long>(h));
  return buf;
}

LayoutParams million(Method m) {
  LayoutParams p;
  p.width_m = p.depth_m = 10000;
  p.method = m;
  p.allow_intersection = 0.2;
  p.retries = 10;
  // Celba's advice: low densities first. 100 trees/ha in all.
  p.species = {rule("oak", 20, 4, 25), rule("birch", 30, 2.5, 18), rule("pine", 50, 2, 20)};
  for (auto& s : p.species) s.min_spacing_m = 3;
  return p;
}

void BM_CelbaMillionTrees(benchmark::State& state) {
  const LayoutParams p = million(Method::kCelba);
  std::size_t placed = 0;
  std::string label;
  for (auto _ : state) {
    Rng rng(1, "layout");
    const LayoutResult r = lay_out(p, rng);
    placed = r.trees.size();
    benchmark::DoNotOptimize(r.trees.data());
    state.PauseTiming();
    label = digest(r);
    state.ResumeTiming();
  }
  state.SetLabel(label);
  state.counters["placed"] = double(placed);
  state.counters["trees/s"] =
      benchmark::Counter(double(placed) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_CelbaMillionTrees)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_PoissonMillionTrees(benchmark::State& state) {
  const LayoutParams p = million(Method::kPoisson);
  std::size_t placed = 0;
  std::string label;
  for (auto _ : state) {
    Rng rng(1, "layout");
    const LayoutResult r = lay_out(p, rng);
    placed = r.trees.size();
    benchmark::DoNotOptimize(r.trees.data());
    state.PauseTiming();
    label = digest(r);
    state.ResumeTiming();
  }
  state.SetLabel(label);
  state.counters["placed"] = double(placed);
  state.counters["points/s"] =
      benchmark::Counter(double(placed) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PoissonMillionTrees)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace sylva::forest

BENCHMARK_MAIN();
