// bench_import: QSM import throughput on canopyHydro_example_tree.csv (9,998 cylinders).
// Run: out/build-imp/stages/import/bench_import   (SYLVA_DATA_DIR or ../shared/data)
// Counters: rows/s = cylinder rows per second for the named phase.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "libs/tree/sylt_format.h"
#include "stages/import/import_file.h"
#include "stages/import/qsm_table.h"
#include "stages/import/qsm_to_tree.h"

namespace {

namespace fs = std::filesystem;

const std::string& example_tree() {
  static const std::string bytes = [] {
    const char* env = std::getenv("SYLVA_DATA_DIR");
    const fs::path dir = env && *env ? fs::path(env) : fs::path("../shared/data");
    std::ifstream in(dir / "qsm" / "canopyHydro_example_tree.csv", std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }();
  return bytes;
}

bool have_data(benchmark::State& state) {
  if (example_tree().empty()) {
    state.SkipWithError("canopyHydro_example_tree.csv not found (set SYLVA_DATA_DIR)");
    return false;
  }
  return true;
}

void set_rows(benchmark::State& state, std::size_t rows) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * rows));
  state.counters["rows/s"] =
      benchmark::Counter(static_cast<double>(rows), benchmark::Counter::kIsIterationInvariantRate);
}

// Text -> checked cylinder table.
void BM_ParseTable(benchmark::State& state) {
  if (!have_data(state)) return;
  std::size_t rows = 0;
  for (auto _ : state) {
    auto table = sylva::import::parse_cylinder_table(example_tree(), "example_tree.csv");
    rows = table.cylinders.size();
    benchmark::DoNotOptimize(table);
  }
  set_rows(state, rows);
}
BENCHMARK(BM_ParseTable)->Unit(benchmark::kMillisecond);

// Table -> tree skeleton.
void BM_TableToTree(benchmark::State& state) {
  if (!have_data(state)) return;
  const auto table = sylva::import::parse_cylinder_table(example_tree(), "example_tree.csv");
  for (auto _ : state) {
    auto t = sylva::import::qsm_to_tree(table, "example_tree.csv");
    benchmark::DoNotOptimize(t);
  }
  set_rows(state, table.cylinders.size());
}
BENCHMARK(BM_TableToTree)->Unit(benchmark::kMillisecond);

// The whole stage core: bytes -> tree -> .sylt bytes (what `import` does minus file I/O).
void BM_ImportToSylt(benchmark::State& state) {
  if (!have_data(state)) return;
  std::size_t rows = 0;
  for (auto _ : state) {
    auto t = sylva::import::import_tree(example_tree(), "example_tree.csv", {});
    auto bytes = sylva::tree::encode_sylt(t);
    benchmark::DoNotOptimize(bytes);
    rows = 9998;
  }
  set_rows(state, rows);
}
BENCHMARK(BM_ImportToSylt)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
