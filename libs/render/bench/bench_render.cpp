// Render-time benchmarks on the headless renderer at 1920x1080 (run: out/.../bench_render).
//  - DenseMesh: one mesh of 500,000 triangles standing in for a full-detail adult tree.
//  - Instanced1000: 1,000 EXT_mesh_gpu_instancing instances of a 2,048-triangle mesh on a
//    32 x 32 grid (a small forest of 2 million triangles).
//  - RealTree / RealTree1000: a GLB sylva wrote (path in $SYLVA_BENCH_TREE, e.g. the default
//    recipe's out/default/mesh_oak/tree.glb: an adult oak with bark, leaf cards and textures),
//    alone and as 1,000 instances on a 32 x 32 grid spaced by the tree's width.
// All load a .glb, so the timings cover exactly what `sylva render` draws. Each iteration is one
// render_views() call: upload + draw + MSAA resolve + read-back; the "views:4" variants render four views per
// upload (items_per_second = views per second).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"
#include "libs/render/testing/gltf_builder.h"

namespace sylva::render {
namespace {

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("sylva-bench-" + std::to_string(::getpid()) + "-" + name);
}

Scene load_and_remove(const testing::GltfBuilder& b, const std::string& name) {
  const auto path = temp_file(name);
  b.write_glb(path);
  Scene s = load_gltf_scene(path);
  std::filesystem::remove(path);
  return s;
}

const Scene& dense_scene() {
  static const Scene scene = [] {
    testing::GltfBuilder b;
    const int m = b.add_material({Vec4(0.35f, 0.5f, 0.2f, 1.f)});
    testing::NodeData n;
    n.mesh = b.add_mesh({testing::dense_grid(500, m)});  // 2 * 500^2 triangles
    b.add_root(b.add_node(n));
    return load_and_remove(b, "dense.glb");
  }();
  return scene;
}

const Scene& instanced_scene() {
  static const Scene scene = [] {
    testing::GltfBuilder b;
    const int m = b.add_material({Vec4(0.35f, 0.5f, 0.2f, 1.f)});
    testing::NodeData n;
    n.mesh = b.add_mesh({testing::dense_grid(32, m)});  // 2,048 triangles
    for (int i = 0; i < 1000; ++i) {
      const float x = float(i % 32) * 1.5f, z = float(i / 32) * 1.5f;
      n.instance_translations.emplace_back(x, 0.5f, z);
      n.instance_rotations.emplace_back(Eigen::AngleAxisf(float(i) * 0.7f, Vec3::UnitY()));
      n.instance_scales.emplace_back(Vec3::Constant(0.8f + 0.4f * float((i * 37) % 11) / 10.f));
    }
    b.add_root(b.add_node(n));
    return load_and_remove(b, "instanced.glb");
  }();
  return scene;
}

// The tree of $SYLVA_BENCH_TREE, or nullptr when the variable is unset.
const Scene* real_tree() {
  static const std::unique_ptr<Scene> scene = []() -> std::unique_ptr<Scene> {
    const char* path = std::getenv("SYLVA_BENCH_TREE");
    if (!path || !*path) return nullptr;
    return std::make_unique<Scene>(load_gltf_scene(path));
  }();
  return scene.get();
}

// 1,000 copies of every mesh of `tree`, on a grid spaced by the tree's horizontal extent.
const Scene* real_forest() {
  static const std::unique_ptr<Scene> scene = []() -> std::unique_ptr<Scene> {
    const Scene* tree = real_tree();
    if (!tree) return nullptr;
    auto forest = std::make_unique<Scene>(*tree);
    const Bounds b = tree->bounds();
    const float step = std::max(b.max.x() - b.min.x(), b.max.z() - b.min.z());
    for (auto& mesh : forest->meshes) {
      const std::vector<Mat4> base = mesh.instances;
      mesh.instances.clear();
      for (int i = 0; i < 1000; ++i) {
        Mat4 t = Mat4::Identity();
        t.block<3, 1>(0, 3) = Vec3(float(i % 32) * step, 0.f, float(i / 32) * step);
        t.block<3, 3>(0, 0) = Eigen::AngleAxisf(float(i) * 0.7f, Vec3::UnitY()).toRotationMatrix();
        for (const Mat4& m : base) mesh.instances.push_back(t * m);
      }
    }
    return forest;
  }();
  return scene.get();
}

Renderer* renderer() {
  static std::unique_ptr<Renderer> r = [] {
    try {
      return Renderer::create_headless();
    } catch (const RenderUnavailableError&) {
      return std::unique_ptr<Renderer>();
    }
  }();
  return r.get();
}

void run(benchmark::State& state, const Scene& scene) {
  Renderer* r = renderer();
  if (!r) {
    state.SkipWithError("headless OpenGL is not available");
    return;
  }
  RenderOptions o;
  o.width = 1920;
  o.height = 1080;
  o.msaa = int(state.range(0));
  const int views = int(state.range(1));
  std::vector<Camera> cams;
  for (int v = 0; v < views; ++v) {
    CameraView cv;
    cv.fov_y_deg = 40;
    cv.placement = OrbitView{30.f + 90.f * float(v), 25.f, 1.0f, 0.f};
    cams.push_back(resolve(cv, scene.bounds(), 1920.f / 1080.f));
  }
  r->render_views(scene, cams, o);  // warm-up: llvmpipe compiles its shader variants on first use
  for (auto _ : state) {
    auto images = r->render_views(scene, cams, o);
    benchmark::DoNotOptimize(images.front().bytes().data());
  }
  state.counters["triangles"] = double(scene.triangle_count());
  state.SetItemsProcessed(std::int64_t(state.iterations()) * views);  // items = views
  state.SetLabel(r->device_description());
}

void BM_DenseMesh500k(benchmark::State& state) { run(state, dense_scene()); }
void run_real(benchmark::State& state, const Scene* scene) {
  if (!scene) {
    state.SkipWithError("set SYLVA_BENCH_TREE to a GLB (e.g. out/default/mesh_oak/tree.glb)");
    return;
  }
  run(state, *scene);
}
void BM_RealTree(benchmark::State& state) { run_real(state, real_tree()); }
void BM_RealTree1000(benchmark::State& state) { run_real(state, real_forest()); }
void BM_Instanced1000(benchmark::State& state) { run(state, instanced_scene()); }

// msaa 4 and 1 at one view, in ms of real time over at least 2 s.
void one_view(benchmark::internal::Benchmark* b) {
  b->ArgNames({"msaa", "views"})
      ->Args({4, 1})
      ->Args({1, 1})
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->MinTime(2.0);
}
// One view as above, and four views at msaa 4.
void one_and_four_views(benchmark::internal::Benchmark* b) {
  one_view(b);
  b->Args({4, 4});
}

BENCHMARK(BM_DenseMesh500k)->Apply(one_and_four_views);
BENCHMARK(BM_Instanced1000)->Apply(one_and_four_views);
BENCHMARK(BM_RealTree)->Apply(one_view);
BENCHMARK(BM_RealTree1000)->Apply(one_view);

}  // namespace
}  // namespace sylva::render

BENCHMARK_MAIN();
