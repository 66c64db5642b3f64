// Developer preview of the mesh stage: meshes a species preset (or a .sylt / QSM file), writes
// the GLB, renders views of it with the headless renderer and prints the statistics.
//   mesh_preview preset configs/species/oak.yaml adult 1 out/oak [subdivision] [max_level]
//   mesh_preview file ../shared/data/qsm/rTwig_QSM.csv - 1 out/qsm [subdivision] [max_level]
// Writes out/oak.glb, out/oak_front.png, out/oak_side.png, out/oak_close.png.
#include <chrono>
#include <cstdio>
#include <string>

#include "libs/fileio/read_file.h"
#include "libs/gltf/writer.h"
#include "libs/image/image_io.h"
#include "libs/render/camera.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"
#include "libs/tree/foliage.h"
#include "stages/generate/card_atlas.h"
#include "stages/generate/preset.h"
#include "stages/generate/textures.h"
#include "stages/generate/weber_penn.h"
#include "stages/import/import_file.h"
#include "stages/mesh/bark_metrics.h"
#include "stages/mesh/tree_mesh.h"

using namespace sylva;

namespace {

std::string png_of(const generate::Rgba8& px, const std::string& path) {
  image::Image img(px.width, px.height);
  img.bytes() = px.pixels;
  image::write_png(img, path);
  return fileio::read_file(path);
}

// The command line: mesh_preview preset|file PATH AGE SEED OUT_PREFIX [SUBDIVISION] [MAX_LEVEL],
// and the environment's switches.
struct Args {
  std::string kind, path, age, out;
  std::uint64_t seed = 0;
  mesh::MeshOptions options;
  bool no_render = false;
};

Args parse_args(int argc, char** argv) {
  Args a;
  a.kind = argv[1];
  a.path = argv[2];
  a.age = argv[3];
  a.out = argv[5];
  a.seed = std::stoull(argv[4]);
  mesh::MeshOptions& o = a.options;
  o.subdivision = argc > 6 ? std::stoi(argv[6]) : 1;
  o.max_level = argc > 7 ? std::stoi(argv[7]) : -1;
  o.count_self_intersections = std::getenv("SELF_INTERSECTIONS") != nullptr;
  o.foliage = std::getenv("NOFOLIAGE") == nullptr;
  if (std::getenv("RING_TOLERANCE")) o.ring_tolerance = std::atof(std::getenv("RING_TOLERANCE"));
  if (std::getenv("SMOOTH_RADIUS")) o.smooth_radius = std::atof(std::getenv("SMOOTH_RADIUS"));
  a.no_render = std::getenv("NORENDER") != nullptr;
  return a;
}

// Generates the preset's tree as the generate stage does (FOLIAGE=cards|single, default cards;
// TEXTURE=size), with its bark and leaf textures (also written as OUT_bark.png, OUT_leaves.png).
tree::Tree preset_tree(const Args& a, mesh::Texture& bark, mesh::Texture& leaves) {
  const auto species = generate::load_species_preset(a.path);
  const bool cards = !std::getenv("FOLIAGE") || std::string(std::getenv("FOLIAGE")) == "cards";
  const int size = std::getenv("TEXTURE") ? std::atoi(std::getenv("TEXTURE")) : 256;
  generate::GenerateOptions g;
  g.max_node_spacing = 0.5;
  g.name = species.species + "/" + a.age;
  Rng brng(a.seed, "bark"), lrng(a.seed, "leaves");
  if (cards) {
    generate::CardAtlas atlas =
        generate::make_card_atlas(species.card, species.leaf, species.bark, size, lrng);
    leaves.bytes = png_of(atlas.image, a.out + "_leaves.png");
    g.atlas = {atlas.columns, atlas.rows, atlas.coverage};
    g.foliage = generate::FoliageMode::kCards;
  } else {
    std::vector<float> coverage;
    leaves.bytes =
        png_of(generate::make_leaf_atlas(species.leaf, size, lrng, &coverage), a.out + "_leaves.png");
    g.atlas = {2, 2, coverage};
  }
  generate::FoliageResult fit;
  g.foliage_result = &fit;
  Rng rng(a.seed, "tree");
  const auto t0 = std::chrono::steady_clock::now();
  tree::Tree t = generate::generate_tree(species.age(a.age).params, g, rng);
  const double gen_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  bark.bytes = png_of(generate::make_bark_texture(species.bark, size, brng), a.out + "_bark.png");
  std::printf("generated in %.1f ms: %zu foliage elements, card scale %.3f, layers %d, LAI %.3f\n", gen_ms,
              fit.elements, fit.card_scale, fit.layers, fit.lai);
  return t;
}

// Trunk diameters at fixed heights and volumes, mesh against skeleton (bark_metrics.h).
void print_bark_metrics(const mesh::TreeMesh& m, const tree::Tree& t, const mesh::MeshOptions& o) {
  const std::vector<char> omit = o.foliage ? tree::twigs_drawn_by_cards(t) : std::vector<char>{};
  const double base = t.branches.front().nodes.front().position.y;
  for (double h : {0.02, 0.1, 1.3, 3.0, 6.0, 10.0, 15.0})
    std::printf(
        "trunk diameter at %.2f m: mesh %.4f skeleton %.4f (%.1f %%)\n", h,
        mesh::trunk_section_diameter(m.bark, t, base + h), mesh::skeleton_diameter(t, base + h),
        100 * mesh::trunk_section_diameter(m.bark, t, base + h) / mesh::skeleton_diameter(t, base + h));
  const double mv = mesh::mesh_volume(m.bark), sv = mesh::skeleton_volume(t, omit),
               so = mesh::skeleton_volume(t, omit, true, o.min_radius);
  double low = 1e9;
  for (const auto& b : t.branches)
    for (const auto& nd : b.nodes) low = std::min(low, nd.position.y - nd.radius);
  std::printf(
      "volume: mesh %.4f skeleton %.4f (%.1f %%), outside parents %.4f (%.1f %%); lowest point %.4f "
      "(base %.4f, skeleton %.4f)\n",
      mv, sv, 100 * mv / sv, so, 100 * mv / so, mesh::lowest_point(m.bark), base, low);
}

// RING_HISTOGRAM: skeleton branches and rings by base radius.
void print_ring_histogram(const mesh::TreeMesh& m, const tree::Tree& t) {
  mesh::SkeletonOptions so;
  so.omit = tree::twigs_drawn_by_cards(t);
  so.ring_tolerance = m.stats.ring_tolerance_m;
  so.corner_scale = 1.4472;
  const mesh::MeshSkeleton sk = mesh::build_skeleton(t, so);
  const double edges[] = {0.005, 0.01, 0.02, 0.04, 0.08, 1e9};
  std::size_t rings[6] = {}, branches[6] = {};
  for (const auto& b : sk.branches) {
    int c = 0;
    while (b.rings.front().radius > edges[c]) ++c;
    rings[c] += b.rings.size();
    ++branches[c];
  }
  for (int c = 0; c < 6; ++c)
    std::printf("base radius <= %g: %zu branches, %zu rings\n", edges[c], branches[c], rings[c]);
}

// Renders OUT.glb from the front, the side and close up into OUT_<view>.png.
void render_views(const std::string& out) {
  const render::Scene rs = render::load_gltf_scene(out + ".glb");
  auto renderer = render::Renderer::create_headless();
  render::RenderOptions ro;
  ro.width = 900;
  ro.height = 900;
  const render::Bounds b = rs.bounds();
  struct View {
    const char* name;
    render::CameraView v;
  };
  std::vector<View> views;
  views.push_back({"front", {"front", render::OrbitView{0, 5, 1.05f, 0}, 40}});
  views.push_back({"side", {"side", render::OrbitView{90, 20, 1.05f, 0}, 40}});
  const float h = b.max.y() - b.min.y();
  const float span = std::max({h, b.max.x() - b.min.x(), b.max.z() - b.min.z()});
  views.push_back(
      {"close",
       {"close",
        render::LookAtView{render::Vec3(span * 0.12f, h * 0.32f, span * 0.16f).cast<double>(),
                           render::Vec3(0, h * 0.28f, 0).cast<double>(), Eigen::Vector3d::UnitY()},
        40}});
  // CLOSE="ex ey ez tx ty tz [fov]" replaces the close-up camera.
  if (const char* c = std::getenv("CLOSE")) {
    float e[7] = {0, 0, 0, 0, 0, 0, 40};
    std::istringstream in(c);
    for (float& x : e) in >> x;
    views.back().v = {
        "close",
        render::LookAtView{render::Vec3(e[0], e[1], e[2]).cast<double>(),
                           render::Vec3(e[3], e[4], e[5]).cast<double>(), Eigen::Vector3d::UnitY()},
        e[6]};
  }
  for (const View& v : views) {
    const render::Camera cam = render::resolve(v.v, b, 1.0f);
    image::write_png(renderer->render(rs, cam, ro), out + "_" + v.name + ".png");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr,
                 "usage: mesh_preview preset|file PATH AGE SEED OUT_PREFIX [SUBDIVISION] [MAX_LEVEL]\n");
    return 2;
  }
  try {
    const Args a = parse_args(argc, argv);
    // 1. The tree: generated from a preset, or imported from a file.
    tree::Tree t;
    mesh::Texture bark{"bark.png", ""}, leaves{"leaves.png", ""};
    if (a.kind == "preset") {
      t = preset_tree(a, bark, leaves);
    } else {
      import::ImportOptions io;
      t = import::import_tree(fileio::read_file(a.path), a.path, io);
    }
    // 2. Mesh it and write OUT.glb.
    const auto t0 = std::chrono::steady_clock::now();
    const mesh::TreeMesh m = mesh::mesh_tree(t, a.options);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const gltf::Scene scene =
        mesh::make_scene(m, t, bark, leaves, {{"statistics", mesh::stats_json(m.stats)}});
    gltf::write_file(scene, a.out + ".glb");
    std::printf("%s\nmeshed in %.1f ms -> %s.glb\n", mesh::stats_json(m.stats).dump(1).c_str(), ms,
                a.out.c_str());
    // 3. Statistics, then the rendered views.
    print_bark_metrics(m, t, a.options);
    if (std::getenv("RING_HISTOGRAM")) print_ring_histogram(m, t);
    if (a.no_render) return 0;
    render_views(a.out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mesh_preview: %s\n", e.what());
    return 1;
  }
  return 0;
}
