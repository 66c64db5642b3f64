// Engine benchmarks (issue 2): the no-op rebuild of a 1,000-node recipe, and action-key hashing
// throughput against raw OpenSSL SHA-256.
//   out/build/bench/bench_engine --benchmark_min_time=1
#include <benchmark/benchmark.h>
#include <openssl/evp.h>

#include <filesystem>
#include <string>

#include "pipeline/cache.h"
#include "pipeline/digest.h"
#include "pipeline/executor.h"
#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/test_support.h"

namespace {

using namespace sylva;

// 500 text nodes, 499 pairwise concats and one sink: 1,000 nodes, 1,497 edges.
std::string recipe_1000() {
  std::string y = "version: 1\nname: bench\nnodes:\n";
  for (int i = 0; i < 500; ++i)
    y += "  n" + std::to_string(i) + ":\n    stage: text\n    with: { text: t" + std::to_string(i) +
         ", count: 10, seed: " + std::to_string(i) + " }\n";
  for (int i = 0; i < 499; ++i)
    y += "  c" + std::to_string(i) + ":\n    stage: concat\n    needs: [n" + std::to_string(i) + ", n" +
         std::to_string(i + 1) + "]\n";
  y += "  all:\n    stage: concat\n    needs: 'c*'\n";
  return y;
}

// recipe_1000() as dir/r.yaml, with the test stages on the real disk.
struct Recipe1000 {
  Recipe1000() {
    test::write_file(dir / "r.yaml", recipe_1000());
    test::register_test_stages(reg, nullptr);
  }
  test::TempDir dir;
  StageRegistry reg;
  RealFileSystem fs;
};

void BM_NoOpRebuild1000(benchmark::State& state) {
  Recipe1000 b;
  SteadyClock clock;
  Diagnostics d;
  auto recipe = load_recipe(b.dir / "r.yaml", b.reg, b.fs, d);
  Cache cache(b.fs, b.dir / "cache");
  BuildEnv env{b.fs, cache, b.dir / "out/bench", clock, nullptr, nullptr};
  BuildOptions opt;
  opt.jobs = static_cast<int>(state.range(0));
  std::string err;
  run_build(*recipe, env, opt, &err);  // the real build, not timed
  std::size_t cached = 0;
  for (auto _ : state) {
    // What `sylva build` does on a no-op: load + check the recipe, then the build itself.
    Diagnostics dd;
    auto r = load_recipe(b.dir / "r.yaml", b.reg, b.fs, dd);
    auto s = run_build(*r, env, opt, &err);
    cached = s.count(NodeStatus::kCached);
  }
  state.counters["nodes_cached"] = static_cast<double>(cached);
}
BENCHMARK(BM_NoOpRebuild1000)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_LoadRecipe1000(benchmark::State& state) {
  Recipe1000 r;
  for (auto _ : state) {
    Diagnostics d;
    benchmark::DoNotOptimize(load_recipe(r.dir / "r.yaml", r.reg, r.fs, d));
  }
}
BENCHMARK(BM_LoadRecipe1000)->Unit(benchmark::kMillisecond);

void BM_Sha256Sylva(benchmark::State& state) {
  const std::string data(static_cast<std::size_t>(state.range(0)), 'x');
  for (auto _ : state) benchmark::DoNotOptimize(digest_bytes(data));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * state.range(0));
}
BENCHMARK(BM_Sha256Sylva)->Arg(1 << 10)->Arg(1 << 20)->Arg(16 << 20);

void BM_Sha256RawOpenSSL(benchmark::State& state) {
  const std::string data(static_cast<std::size_t>(state.range(0)), 'x');
  unsigned char out[32];
  unsigned int len = 0;
  for (auto _ : state) {
    EVP_Digest(data.data(), data.size(), out, &len, EVP_sha256(), nullptr);
    benchmark::DoNotOptimize(out);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * state.range(0));
}
BENCHMARK(BM_Sha256RawOpenSSL)->Arg(1 << 10)->Arg(1 << 20)->Arg(16 << 20);

// Hashing a file through digest_file (1 MiB reads), as the engine does for file parameters.
void BM_DigestFile16MiB(benchmark::State& state) {
  test::TempDir dir;
  test::write_file(dir / "f.bin", std::string(16 << 20, 'y'));
  for (auto _ : state) benchmark::DoNotOptimize(digest_file(dir / "f.bin"));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * (16 << 20));
}
BENCHMARK(BM_DigestFile16MiB);

}  // namespace

BENCHMARK_MAIN();
