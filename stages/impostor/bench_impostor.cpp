// Benchmark (a separate executable, never a timed test): baking an adult tree's impostor on
// llvmpipe, from the LOD level the stage chooses, and what the outputs weigh.
//
//   SYLVA_BENCH_LOD=out/default/lod_oak out/build/stages/impostor/bench_impostor
//
// BM_Bake/<kind>/<contexts>: the GL bake (layout, draws, read-back, dilation, cutouts, the GLB),
// wall time; counters: the bake's CPU seconds over all threads (bake_cpu_s) and those of
// llvmpipe's rasteriser threads (raster_cpu_s; the machine's load does not change them much, so
// they compare levers), frames, source primitives, drawn primitives per frame (lines merged,
// line_merge.h), GLB bytes and atlas PNG bytes (colour + normal, encoded as the stage encodes
// them: atlas_png.h, outside the timed loop; SYLVA_BENCH_NO_PNG=1 skips them, so that the
// process's CPU under `time` is the bake's and the level's loading).
// BM_EncodeMaps: the two 4096^2 PNG encodes the stage adds after the bake.
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "libs/image/png.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/line_merge.h"
#include "stages/impostor/atlas_png.h"
#include "stages/impostor/bake.h"
#include "stages/impostor/source.h"

namespace {

using namespace sylva;
namespace fs = std::filesystem;

// CPU seconds (user + system) of the whole process so far: every thread, llvmpipe's included.
double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

// CPU seconds (user + system) of this process's threads named "llvmpipe-*" (Mesa llvmpipe's
// rasteriser threads: binned triangles, fragment shaders, depth, blending), from /proc.
double rasteriser_cpu_s() {
  double sum = 0;
  const double tick = double(sysconf(_SC_CLK_TCK));
  for (const auto& e : fs::directory_iterator("/proc/self/task")) {
    std::ifstream comm(e.path() / "comm");
    std::string name;
    std::getline(comm, name);
    if (name.rfind("llvmpipe-", 0) != 0) continue;
    std::ifstream stat(e.path() / "stat");
    std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
    std::istringstream rest(text.substr(text.rfind(')') + 2));  // fields from 3 (state) on
    std::string field;
    for (int i = 3; i < 14; ++i) rest >> field;
    double utime = 0, stime = 0;
    rest >> utime >> stime;  // fields 14, 15
    sum += (utime + stime) / tick;
  }
  return sum;
}

struct Source {
  render::Scene scene;
  impostor::SourceDesc desc;
};

// The level the stage would bake for `params` (stages/impostor/source.h), loaded once.
const Source& source(const impostor::BakeParams& params) {
  static const Source s = [&] {
    const char* dir = std::getenv("SYLVA_BENCH_LOD");
    if (!dir)
      throw std::runtime_error("set SYLVA_BENCH_LOD to a built lod node's directory (out/default/lod_oak)");
    const auto levels =
        impostor::lod_level_refs(lodchain::read_lod_chain((fs::path(dir) / lodchain::kSummaryFile).string()));
    Source out;
    out.desc = impostor::choose_source(levels, render::load_gltf_scene(fs::path(dir) / levels.back().file),
                                       params.layout);
    out.scene = render::load_gltf_scene(fs::path(dir) / out.desc.file);
    return out;
  }();
  return s;
}

void BM_Bake(benchmark::State& state) {
  impostor::BakeParams p;  // the stage's defaults: 16 x 16 frames of 256 px
  p.layout.kind = state.range(0) == 0 ? impostor::Kind::kHemiOctahedral : impostor::Kind::kBillboards;
  p.threads = int(state.range(1));
  const Source& s = source(impostor::BakeParams{});
  impostor::BakeOutput out;
  const double cpu0 = process_cpu_s(), rast0 = rasteriser_cpu_s();
  for (auto _ : state) out = impostor::bake_impostor(render::shared_impostor_renderer(), s.scene, p, s.desc);
  // The bake's CPU over all threads (the timed loop's CPU column is the main thread's only).
  state.counters["bake_cpu_s"] = (process_cpu_s() - cpu0) / double(state.iterations());
  state.counters["raster_cpu_s"] = (rasteriser_cpu_s() - rast0) / double(state.iterations());
  state.counters["frames"] = double(p.layout.kind == impostor::Kind::kBillboards
                                        ? out.info.cards.size()
                                        : std::size_t(p.layout.frames_per_side * p.layout.frames_per_side));
  state.counters["source_primitives"] = double(s.scene.triangle_count() + s.scene.line_count());
  state.counters["source_level"] = s.desc.level;
  // What the baker rasterises per frame: triangles, and lines after merging (line_merge.h).
  std::size_t drawn = s.scene.triangle_count();
  for (const render::Mesh& m : s.scene.meshes)
    for (const render::Primitive& prim : m.primitives) {
      if (prim.topology != render::Topology::kLines) continue;
      const bool blend = prim.material >= 0 && s.scene.materials[std::size_t(prim.material)].alpha_mode ==
                                                   render::AlphaMode::kBlend;
      drawn += (blend ? render::merge_coincident_lines(prim).positions.size() / 2 : prim.indices.size() / 2) *
               m.instances.size();
    }
  state.counters["drawn_primitives"] = double(drawn);
  state.counters["glb_bytes"] = double(out.glb.size());
  state.counters["glb_triangles"] = double(out.info.glb_triangles);
  if (std::getenv("SYLVA_BENCH_NO_PNG")) return;  // the encodes' CPU would hide the bake's in `time`
  const impostor::AtlasPngs png = impostor::encode_atlas_pngs(out.color, out.normal_depth);  // as the stage
  state.counters["atlas_png_bytes"] = double(png.color.size() + png.normal_depth.size());
}
BENCHMARK(BM_Bake)
    ->ArgsProduct({{0}, {1, 2}})
    ->Args({1, 2})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

// BM_EncodeMaps/<zlib level>: the two maps' PNG encodes at that level (the stage's is kPngLevel).
void BM_EncodeMaps(benchmark::State& state) {
  const Source& s = source(impostor::BakeParams{});
  static const impostor::BakeOutput out =
      impostor::bake_impostor(render::shared_impostor_renderer(), s.scene, {}, s.desc);
  image::PngOptions o;
  o.zlib_level = int(state.range(0));
  std::size_t bytes = 0;
  for (auto _ : state)
    bytes = image::encode_png(out.color, o).size() + image::encode_png(out.normal_depth, o).size();
  state.counters["bytes"] = double(bytes);
}
BENCHMARK(BM_EncodeMaps)
    ->Arg(6)
    ->Arg(3)
    ->Arg(2)
    ->Arg(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
