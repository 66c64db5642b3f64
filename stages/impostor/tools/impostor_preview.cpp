// Developer preview: bake an impostor from a GLB and render it beside the source.
// usage: impostor_preview IN.glb OUT_DIR [kind] [frames] [frame_px] [line_pixel_m]
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "libs/image/image_io.h"
#include "libs/image/resample.h"
#include "libs/render/gltf_scene.h"
#include "libs/gltf/writer.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/renderer.h"
#include "stages/impostor/bake.h"
#include "stages/impostor/check/impostorcheck.h"

using namespace sylva;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: impostor_preview IN.glb OUT_DIR [kind] [frames] [frame_px] [line_pixel_m]\n");
    return 2;
  }
  const std::filesystem::path out = argv[2];
  std::filesystem::create_directories(out);
  render::Scene scene = render::load_gltf_scene(argv[1]);
  if (const char* drop = std::getenv("PREVIEW_DROP")) {  // "lines" or "triangles": timing experiments
    for (auto& m : scene.meshes)
      std::erase_if(m.primitives, [&](const render::Primitive& p) {
        return (std::string(drop) == "lines") == (p.topology == render::Topology::kLines);
      });
  }
  impostor::BakeParams p;
  if (const char* m = std::getenv("PREVIEW_MIP")) p.layout.mip_levels = std::atoi(m);
  if (const char* m = std::getenv("PREVIEW_MSAA")) p.msaa = std::atoi(m);
  const std::string kind = argc > 3 ? argv[3] : "hemi_octahedral";
  p.layout.kind = kind == "octahedral" ? impostor::Kind::kOctahedral
                  : kind == "billboards" ? impostor::Kind::kBillboards : impostor::Kind::kHemiOctahedral;
  if (argc > 4) p.layout.frames_per_side = std::atoi(argv[4]);
  if (argc > 5) p.layout.frame_px = std::atoi(argv[5]);
  impostor::SourceDesc src;
  src.file = argv[1];
  if (argc > 6) src.line_pixel_m = std::atof(argv[6]);
  auto& ir = render::shared_impostor_renderer();
  const auto t0 = std::chrono::steady_clock::now();
  impostor::BakeOutput b = impostor::bake_impostor(ir, scene, p, src);
  const auto t1 = std::chrono::steady_clock::now();
  std::fprintf(stderr, "bake %.2f s (%zu triangles, %zu lines), switch %.1f m, eps %.3f (texel %.3f view %.3f)\n",
               std::chrono::duration<double>(t1 - t0).count(), scene.triangle_count(), scene.line_count(),
               b.info.switch_distance_m, b.info.error.epsilon_m(), b.info.error.texel_m, b.info.error.view_m);
  image::write_png(b.color, out / "impostor_color.png");
  image::write_png(b.normal_depth, out / "impostor_normal.png");
  std::ofstream(out / "impostor.glb", std::ios::binary) << b.glb;
  std::ofstream(out / "impostor.json") << impostor::write_impostor_json(b.info);
  const auto t2 = std::chrono::steady_clock::now();
  std::fprintf(stderr, "write %.2f s\n", std::chrono::duration<double>(t2 - t1).count());
  if (const char* ref = std::getenv("PREVIEW_REF")) {
    const render::Scene full = render::load_gltf_scene(ref);
    impostor::ImpostorSubject sub;
    sub.label = "preview";
    sub.info = b.info;
    sub.octahedral.color = b.color;
    sub.octahedral.normal_depth = b.normal_depth;
    sub.octahedral.frames_per_side = b.info.frames_per_side;
    sub.octahedral.hemi = b.info.hemi;
    sub.octahedral.center = render::Vec3(float(b.info.sphere_center[0]), float(b.info.sphere_center[1]), float(b.info.sphere_center[2]));
    sub.octahedral.radius = float(b.info.sphere_radius);
    sub.octahedral.half_extent = float(b.info.frame_half_extent);
    sub.octahedral.frame_px = b.info.frame_px;
    sub.octahedral.padding_px = b.info.padding_px;
    sub.octahedral.mip_levels = b.info.mip_levels;
    if (b.info.kind == impostor::Kind::kBillboards) sub.cards = render::load_gltf_scene_from_memory(b.glb, "impostor.glb");
    if (const char* lod = std::getenv("PREVIEW_AS_CARDS")) {  // measure another model the same way
      sub.info.kind = impostor::Kind::kBillboards;
      sub.cards = render::load_gltf_scene(lod);
      if (const char* d = std::getenv("PREVIEW_DIST")) sub.info.switch_distance_m = std::atof(d);
    }
    impostor::ImpostorCheckOptions co;
    if (const char* s = std::getenv("PREVIEW_SCALE")) co.distance_scale = std::atof(s);
    auto renderer = render::Renderer::create_headless();
    int n = 0;
    const auto results = impostor::check_impostor(*renderer, ir, full, sub, co,
        [&](const impostor::ImpostorViewCheck& c, const image::Image& f, const image::Image& t, const image::Image& d) {
          if (n++ % 5 == 0) {
            image::write_png(f, out / ("full_" + c.view + ".png"));
            image::write_png(t, out / ("imp_" + c.view + ".png"));
            image::write_png(d, out / ("diff_" + c.view + ".png"));
          }
        });
    for (const auto& c : results)
      std::printf("%-14s frame %5.1f deg  fp %5zu fail %6.3f%% cov %.4f bias %+.4f rgb %.4f shade %.4f %s\n", c.view.c_str(),
                  c.frame_angle_deg, c.footprint_pixels, 100 * c.coverage_failing_fraction, c.coverage_mean_error,
                  c.coverage_bias, c.colour_mean_error, c.shade_mean_error, c.passed ? "ok" : c.failure.c_str());
  }
  return 0;
}
