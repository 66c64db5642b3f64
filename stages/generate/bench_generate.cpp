// Generation time and skeleton size for every adult species preset (configs/species/*.yaml),
// with the stage's default options (max_node_spacing_m 0.5, leaf_density 1). Goal (issue 3): an
// adult broadleaf preset with >= 100,000 skeleton nodes in under 100 ms.
//   cmake -S . -B out/build-gen-rel -G Ninja -DCMAKE_BUILD_TYPE=Release
//   cmake --build out/build-gen-rel --target bench_generate -j2
//   out/build-gen-rel/stages/generate/bench_generate
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>

#include "libs/tree/tree.h"
#include "stages/generate/preset.h"
#include "stages/generate/textures.h"
#include "stages/generate/weber_penn.h"

namespace {

using namespace sylva;

void bm_generate(benchmark::State& state, generate::Preset preset) {
  generate::GenerateOptions o;
  o.max_node_spacing = 0.5;
  std::size_t nodes = 0, branches = 0, foliage = 0;
  for (auto _ : state) {
    Rng rng(1, "tree");
    const tree::Tree t = generate::generate_tree(preset, o, rng);
    benchmark::DoNotOptimize(t.branches.data());
    nodes = 0;
    for (const auto& b : t.branches) nodes += b.nodes.size();
    branches = t.branches.size();
    foliage = t.leaves.size() + t.needles.size();
  }
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["branches"] = static_cast<double>(branches);
  state.counters["foliage"] = static_cast<double>(foliage);
  state.counters["nodes_per_s"] =
      benchmark::Counter(static_cast<double>(nodes), benchmark::Counter::kIsIterationInvariantRate);
}

// The two textures at the stage's default size.
void bm_textures(benchmark::State& state, generate::BarkLook bark, generate::LeafLook leaf) {
  for (auto _ : state) {
    Rng a(1, "bark"), b(1, "leaves");
    const generate::Rgba8 x = generate::make_bark_texture(bark, 512, a);
    const generate::Rgba8 y = generate::make_leaf_atlas(leaf, 512, b);
    benchmark::DoNotOptimize(x.pixels.data());
    benchmark::DoNotOptimize(y.pixels.data());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::filesystem::path> files =
      generate::species_preset_files(std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species");
  for (const auto& f : files) {
    const generate::SpeciesPreset s = generate::load_species_preset(f);
    benchmark::RegisterBenchmark(("generate/" + s.species + "/adult").c_str(), bm_generate,
                                 s.age("adult").params)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("textures512/" + s.species).c_str(), bm_textures, s.bark, s.leaf)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
