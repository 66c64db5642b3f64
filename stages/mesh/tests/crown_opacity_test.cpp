// Crown opacity (crown_opacity.h): the measure itself on drawn images, and every adult preset's
// crown, generated with twig/shoot cards as the generate stage does (seed 1, 256 px atlas as the
// default recipe, mip-safe alpha), meshed at the default options and rendered from the side at
// azimuth 0 and 90 (elevation 0, 512 px, fov 40°, the bounding sphere filling the frame),
// against a floor per preset (issue 9: goal 0.75 for broadleaves, 0.65 for conifers; the table
// of measured values is in docs/performance.md, "Trees in leaf").
#include "stages/mesh/crown_opacity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "libs/gltf/writer.h"
#include "libs/image/png.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"
#include "stages/generate/card_atlas.h"
#include "stages/generate/mip_safe_alpha.h"
#include "stages/generate/preset.h"
#include "stages/generate/textures.h"
#include "stages/generate/weber_penn.h"
#include "stages/mesh/tests/test_trees.h"
#include "stages/mesh/tree_mesh.h"

namespace sylva::mesh {
namespace {

image::Image blank(int w, int h) { return image::Image(w, h, image::Rgba8{0, 0, 0, 0}); }
void fill(image::Image& img, int x0, int x1, int y0, int y1) {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) img.set(x, y, {10, 80, 10, 255});
}

TEST(CrownOpacity, FullCrownOnATrunkIsOne) {
  image::Image img = blank(100, 100);
  fill(img, 20, 80, 10, 60);  // crown, 60 px wide
  fill(img, 47, 53, 60, 95);  // trunk, 6 px: not a crown row
  const CrownOpacity c = crown_opacity(img);
  EXPECT_EQ(c.tree_width, 60);
  EXPECT_EQ(c.crown_rows, 50);
  EXPECT_DOUBLE_EQ(c.opacity, 1.0);
}

TEST(CrownOpacity, HolesAndGapsCount) {
  image::Image img = blank(100, 100);
  // Every other column covered between 20 and 79: 30 of 59 pixels in each row's span.
  for (int x = 20; x < 80; x += 2) fill(img, x, x + 1, 10, 50);
  const CrownOpacity c = crown_opacity(img);
  EXPECT_EQ(c.crown_rows, 40);
  EXPECT_NEAR(c.opacity, 30.0 / 59.0, 1e-12);
  // Half-transparent pixels are not covered; an empty image has no crown.
  image::Image faint = blank(10, 10);
  for (int x = 0; x < 10; ++x) faint.set(x, 5, {0, 0, 0, 127});
  EXPECT_EQ(crown_opacity(faint).crown_rows, 0);
  EXPECT_EQ(crown_opacity(blank(8, 8)).opacity, 0.0);
}

// The adult tree of `preset` as the default recipe makes it, as a renderable scene.
render::Scene adult_scene(const std::filesystem::path& preset) {
  const generate::SpeciesPreset species = generate::load_species_preset(preset);
  const test::CardTree cards = test::adult_card_tree(species, 256, 1);
  const TreeMesh m = mesh_tree(cards.tree, MeshOptions{});
  const gltf::Scene scene = make_scene(m, cards.tree, Texture{"bark.png", ""},
                                       Texture{"leaves.png", test::png_bytes(cards.atlas.image)}, {});
  return render::load_gltf_scene_from_memory(gltf::encode(scene), preset.stem().string() + ".glb");
}

// Floors: the goal, 0.75 for broadleaves and 0.65 for conifers; every adult preset meets
// it as drawn (docs/performance.md, "Trees in leaf").
const std::map<std::string, double> kFloor = {
    {"birch", 0.75}, {"holly", 0.75},      {"mugo_pine", 0.65},      {"norway_spruce", 0.65},
    {"oak", 0.75},   {"scots_pine", 0.65}, {"weeping_willow", 0.75}, {"white_poplar", 0.75},
};

TEST(CrownOpacity, EveryAdultPresetMeetsItsFloor) {
  std::unique_ptr<render::Renderer> renderer;
  try {
    renderer = render::Renderer::create_headless();
  } catch (const render::RenderUnavailableError& e) {
    GTEST_SKIP() << e.what();
  }
  render::RenderOptions ro;
  ro.width = ro.height = 512;
  ro.background = {0, 0, 0, 0};
  for (const auto& preset : test::species_presets()) {
    const render::Scene scene = adult_scene(preset);
    std::vector<render::Camera> cams;
    for (float az : {0.f, 90.f})
      cams.push_back(render::resolve({"side", render::OrbitView{az, 0, 1, 0}, 40}, scene.bounds(), 1.f));
    const auto images = renderer->render_views(scene, cams, ro);
    const double a = crown_opacity(images[0]).opacity, b = crown_opacity(images[1]).opacity;
    // The same views sampling the full-resolution atlas (no mipmaps): the leaves' own opacity,
    // without the mip-safe halo's thickening of cards a few pixels long (reported, not asserted).
    render::Scene flat = scene;
    for (auto& t : flat.textures) t.mipmaps = false;
    const auto full = renderer->render_views(flat, cams, ro);
    const double fa = crown_opacity(full[0]).opacity, fb = crown_opacity(full[1]).opacity;
    const std::string name = preset.stem().string();
    std::printf("[ opacity  ] %s: %.3f (azimuth 0) %.3f (azimuth 90) mean %.3f; without mipmaps mean %.3f\n",
                name.c_str(), a, b, (a + b) / 2, (fa + fb) / 2);
    ASSERT_TRUE(kFloor.count(name)) << name;
    EXPECT_GE((a + b) / 2, kFloor.at(name)) << name;
    EXPECT_GE(std::min(a, b), kFloor.at(name) - 0.05) << name;
  }
}

double srgb_to_linear(int c) {
  const double v = c / 255.0;
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// Mean alpha of an image and the alpha-weighted mean linear colour of what covers it.
struct Look {
  double coverage = 0, r = 0, g = 0, b = 0;
  double greenness() const { return g / std::max(r + b, 1e-9); }
};
Look look_of(const image::Image& img) {
  Look l;
  double a_sum = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) {
      const image::Rgba8 p = img.at(x, y);
      const double a = p.a / 255.0;
      a_sum += a;
      l.r += srgb_to_linear(p.r) * a, l.g += srgb_to_linear(p.g) * a, l.b += srgb_to_linear(p.b) * a;
    }
  l.coverage = a_sum / (static_cast<double>(img.width()) * img.height());
  if (a_sum > 0) l.r /= a_sum, l.g /= a_sum, l.b /= a_sum;
  return l;
}

// Far trees keep their leaves (issue 9): an adult birch and Scots pine drawn small (the tree 64
// px high, where a card is two or three pixels long and clients sample the atlas's coarse
// mipmaps, lod 6-7) keep, against the same view drawn without mipmaps (every pixel samples the
// full-resolution atlas: an unbiased estimate of the leaves' true coverage), between 0.8 and 1.6
// of its coverage and at least 0.85 of its greenness g / (r + b); and large (512 px) the crown is
// within 0.9-1.3 of it. Without a mip-safe atlas the small trees lose their leaves
// coverage and turn white (birch bark) or orange (pine bark): measured x0.14 of the coverage and
// 0.5 (birch) and 0.3 (pine) of the greenness.
TEST(FarCrown, CardsKeepCoverageAndColourWhenSmall) {
  std::unique_ptr<render::Renderer> renderer;
  try {
    renderer = render::Renderer::create_headless();
  } catch (const render::RenderUnavailableError& e) {
    GTEST_SKIP() << e.what();
  }
  for (const char* name : {"birch", "scots_pine"}) {
    const render::Scene scene = adult_scene(std::filesystem::path(SYLVA_SOURCE_DIR) / "configs/species" /
                                            (std::string(name) + ".yaml"));
    render::Scene flat = scene;
    for (auto& t : flat.textures) t.mipmaps = false;
    const std::vector<render::Camera> cams{
        render::resolve({"side", render::OrbitView{0, 0, 1, 0}, 40}, scene.bounds(), 1.f)};
    for (int size : {512, 64}) {
      render::RenderOptions ro;
      ro.width = ro.height = size;
      ro.background = {0, 0, 0, 0};
      const Look drawn = look_of(renderer->render_views(scene, cams, ro)[0]);
      const Look truth = look_of(renderer->render_views(flat, cams, ro)[0]);
      const double ratio = drawn.coverage / truth.coverage;
      std::printf(
          "[ far      ] %s %d px: coverage %.4f vs %.4f without mipmaps (x%.2f), greenness %.2f vs %.2f\n",
          name, size, drawn.coverage, truth.coverage, ratio, drawn.greenness(), truth.greenness());
      EXPECT_GE(ratio, size == 64 ? 0.8 : 0.9) << name << " " << size;
      EXPECT_LE(ratio, size == 64 ? 1.6 : 1.3) << name << " " << size;
      EXPECT_GE(drawn.greenness(), 0.85 * truth.greenness()) << name << " " << size;
    }
  }
}

}  // namespace
}  // namespace sylva::mesh
