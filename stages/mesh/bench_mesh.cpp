// Mesh stage benchmark (a separate executable, never a timed unit test): for every adult species
// preset (configs/species/*.yaml, seed 1, the generate stage's defaults) and subdivision 0, 1, 2,
// the time of mesh_tree() — skeleton, box joints, topology check, Catmull–Clark, normals,
// tangents, seams, foliage — and quads generated per second. Goal (issue 4): an adult broadleaf
// preset meshed and subdivided twice in under 1 s.
//   cmake -S . -B out/build-mesh-rel -G Ninja -DCMAKE_BUILD_TYPE=Release
//   cmake --build out/build-mesh-rel --target bench_mesh -j2
//   out/build-mesh-rel/stages/mesh/bench_mesh
// Also: phase/oak/adult/subdivision:2/phase:N times the phases separately — 0 skeleton, 1 box
// joints, 2 half-edge check, 3 Catmull-Clark (native), 4 glTF surface, 5 Catmull-Clark
// (OpenMesh), 6 OpenMesh topology check — and gltf/oak/adult encodes the default-options scene.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "libs/gltf/writer.h"
#include "pipeline/rng.h"
#include "stages/generate/preset.h"
#include "stages/generate/weber_penn.h"
#include "stages/mesh/box_joints.h"
#include "stages/mesh/subdivision.h"
#include "stages/mesh/surface.h"
#include "stages/mesh/topology_check.h"
#include "stages/mesh/tree_mesh.h"

namespace {

using namespace sylva;

const tree::Tree& adult_tree(const std::filesystem::path& preset) {
  static std::map<std::string, tree::Tree> cache;
  auto it = cache.find(preset.string());
  if (it != cache.end()) return it->second;
  const generate::SpeciesPreset s = generate::load_species_preset(preset);
  generate::GenerateOptions o;
  o.max_node_spacing = 0.5;
  Rng rng(1, "tree");
  return cache.emplace(preset.string(), generate::generate_tree(s.age("adult").params, o, rng)).first->second;
}

void mesh_tree_bench(benchmark::State& state, std::filesystem::path preset) {
  const tree::Tree& t = adult_tree(preset);
  mesh::MeshOptions o;
  o.subdivision = static_cast<int>(state.range(0));
  std::size_t quads = 0, base = 0;
  for (auto _ : state) {
    const mesh::TreeMesh m = mesh::mesh_tree(t, o);
    benchmark::DoNotOptimize(m.bark_surface.positions.data());
    quads = m.stats.quads;
    base = m.stats.base_quads;
  }
  state.counters["base_quads"] = static_cast<double>(base);
  state.counters["quads"] = static_cast<double>(quads);
  state.counters["quads_per_s"] =
      benchmark::Counter(static_cast<double>(quads), benchmark::Counter::kIsIterationInvariantRate);
}

// The phases of mesh_tree for one preset, to see where the time goes.
void phases(benchmark::State& state, std::filesystem::path preset) {
  const tree::Tree& t = adult_tree(preset);
  const int levels = static_cast<int>(state.range(0));
  const int phase = static_cast<int>(state.range(1));
  const double k = mesh::corner_scale_for_subdivision(levels);
  mesh::SkeletonOptions so;
  so.corner_scale = k;
  mesh::BarkOptions bo;
  bo.corner_scale = k;
  const mesh::MeshSkeleton sk = mesh::build_skeleton(t, so);
  const mesh::QuadMesh base = mesh::build_bark_mesh(sk, bo, nullptr);
  const mesh::QuadMesh fine = mesh::subdivide(base, levels);
  for (auto _ : state) {
    switch (phase) {
      case 0:
        benchmark::DoNotOptimize(mesh::build_skeleton(t, so).branches.data());
        break;
      case 1:
        benchmark::DoNotOptimize(mesh::build_bark_mesh(sk, bo, nullptr).quads.data());
        break;
      case 2:
        benchmark::DoNotOptimize(mesh::check_topology_fast(base).euler);
        break;
      case 3:
        benchmark::DoNotOptimize(mesh::subdivide(base, levels).quads.data());
        break;
      case 4:
        benchmark::DoNotOptimize(mesh::to_primitive(fine).indices.data());
        break;
      case 5:
        benchmark::DoNotOptimize(mesh::subdivide(base, levels, mesh::Subdivider::kOpenMesh).quads.data());
        break;
      default:
        benchmark::DoNotOptimize(mesh::check_topology(base).euler);
        break;
    }
  }
}

void encode(benchmark::State& state, std::filesystem::path preset) {
  const tree::Tree& t = adult_tree(preset);
  const mesh::TreeMesh m = mesh::mesh_tree(t, mesh::MeshOptions{});
  const gltf::Scene scene = mesh::make_scene(m, t, {}, {}, {{"statistics", mesh::stats_json(m.stats)}});
  std::size_t bytes = 0;
  for (auto _ : state) bytes = gltf::encode(scene).size();
  state.counters["MB"] = static_cast<double>(bytes) / 1e6;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::filesystem::path> files =
      generate::species_preset_files(std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species");
  for (const auto& f : files) {
    const std::string name = f.stem().string();
    benchmark::RegisterBenchmark(("mesh/" + name + "/adult").c_str(), mesh_tree_bench, f)
        ->ArgName("subdivision")
        ->DenseRange(0, 2)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime()
        ->UseRealTime();
  }
  const std::filesystem::path oak = std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species/oak.yaml";
  benchmark::RegisterBenchmark("phase/oak/adult", phases, oak)
      ->ArgNames({"subdivision", "phase"})
      ->ArgsProduct({{2}, {0, 1, 2, 3, 4, 5, 6}})
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("gltf/oak/adult", encode, oak)->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
