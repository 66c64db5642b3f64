// Developer preview: build the LOD chain of a preset, write lod<i>.glb and render every level
// from a fixed camera (all levels side by side in one PNG row per camera distance) with libs/render.
//   lod_preview <species> <young|middle|adult> <out_dir> [distance_m]
#include <cstdio>
#include <filesystem>
#include <string>

#include "libs/gltf/writer.h"
#include "libs/image/image_io.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"
#include "pipeline/rng.h"
#include "stages/generate/preset.h"
#include "stages/generate/weber_penn.h"
#include "stages/lod/chain.h"
#include "stages/lod/lod_gltf.h"

int main(int argc, char** argv) {
  using namespace sylva;
  if (argc < 4) {
    std::fprintf(stderr, "usage: lod_preview <species> <age> <out_dir> [distance_m]\n");
    return 2;
  }
  const std::filesystem::path out = argv[3];
  std::filesystem::create_directories(out);
  const auto sp = generate::load_species_preset(std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species" /
                                                (std::string(argv[1]) + ".yaml"));
  generate::GenerateOptions go;
  go.max_node_spacing = 0.5;
  Rng rng(1, "tree");
  tree::Tree t = generate::generate_tree(sp.age(argv[2]).params, go, rng);
  lod::ChainOptions o;
  const auto levels = lod::build_chain(t, o);
  const double h = lod::tree_height(t);
  auto renderer = render::Renderer::create_headless();
  render::RenderOptions ro;
  ro.width = 512;
  ro.height = 512;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const auto file = out / ("lod" + std::to_string(i) + ".glb");
    gltf::write_file(lod::level_scene(t, levels[i], i, {}), file);
    const render::Scene scene = render::load_gltf_scene(file);
    render::Camera cam;
    const double d = argc > 4 ? std::stod(argv[4]) : 1.6 * h;
    cam.eye = render::Vec3(0, static_cast<float>(h / 2), static_cast<float>(d));
    cam.target = render::Vec3(0, static_cast<float>(h / 2), 0);
    cam.fov_y_deg = 45;
    cam.z_far = static_cast<float>(d * 4);
    const image::Image img = renderer->render(scene, cam, ro);
    image::write_png(img, out / ("lod" + std::to_string(i) + ".png"));
    const auto& c = levels[i].counts;
    std::printf(
        "lod%zu eps %.4f m switch %.1f m: quads %zu tris %zu lines %zu leaves %zu needles %zu/%zu alpha "
        "%.3f\n",
        i, levels[i].spec.epsilon, levels[i].spec.switch_distance, c.quads, c.triangles, c.lines, c.leaves,
        c.needle_lines, c.needle_quads, levels[i].line_alpha);
  }
  return 0;
}
