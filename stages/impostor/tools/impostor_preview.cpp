// Developer preview: bake an impostor from a GLB and write its four files, with the time the
// bake took. usage: impostor_preview IN.glb OUT_DIR [kind] [frames] [frame_px]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "libs/image/image_io.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/impostor_renderer.h"
#include "stages/impostor/bake.h"

using namespace sylva;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: impostor_preview IN.glb OUT_DIR [hemi_octahedral|octahedral|billboards] [frames] "
                 "[frame_px]\n");
    return 2;
  }
  const std::filesystem::path out = argv[2];
  std::filesystem::create_directories(out);
  const render::Scene scene = render::load_gltf_scene(argv[1]);
  impostor::BakeParams p;
  const std::string kind = argc > 3 ? argv[3] : "hemi_octahedral";
  p.layout.kind = kind == "octahedral"   ? impostor::Kind::kOctahedral
                  : kind == "billboards" ? impostor::Kind::kBillboards
                                         : impostor::Kind::kHemiOctahedral;
  if (argc > 4) p.layout.frames_per_side = std::atoi(argv[4]);
  if (argc > 5) p.layout.frame_px = std::atoi(argv[5]);
  if (const char* t = std::getenv("IMPOSTOR_THREADS")) p.threads = std::atoi(t);
  impostor::SourceDesc src;
  src.file = std::filesystem::path(argv[1]).filename().string();
  const auto t0 = std::chrono::steady_clock::now();
  const impostor::BakeOutput b = impostor::bake_impostor(render::shared_impostor_renderer(), scene, p, src);
  const auto t1 = std::chrono::steady_clock::now();
  image::write_png(b.color, out / b.info.color_map);
  image::write_png(b.normal_depth, out / b.info.normal_depth_map);
  std::ofstream(out / "impostor.glb", std::ios::binary) << b.glb;
  std::ofstream(out / "impostor.json") << impostor::write_impostor_json(b.info);
  std::fprintf(stderr,
               "%s: baked in %.2f s (%zu triangles, %zu lines); switch distance %.1f m; written to %s\n",
               argv[1], std::chrono::duration<double>(t1 - t0).count(), scene.triangle_count(),
               scene.line_count(), b.info.switch_distance_m, out.c_str());
  return 0;
}
