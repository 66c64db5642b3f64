#include "stages/generate/textures.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "stages/generate/card_atlas.h"
#include "stages/generate/mip_safe_alpha.h"
#include "stages/generate/preset.h"

namespace sylva::generate {
namespace {

int channel(const Rgba8& img, int x, int y, int c) {
  return img.pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) +
                     static_cast<std::size_t>(x)) *
                        4 +
                    static_cast<std::size_t>(c)];
}

// Mean absolute RGB difference between columns (or rows) a and b.
double line_diff(const Rgba8& img, int a, int b, bool columns) {
  double sum = 0;
  for (int i = 0; i < img.width; ++i)
    for (int c = 0; c < 3; ++c)
      sum += std::abs(columns ? channel(img, a, i, c) - channel(img, b, i, c)
                              : channel(img, i, a, c) - channel(img, i, b, c));
  return sum / (img.width * 3);
}

// Same Rng state -> same pixels; another seed -> different pixels.
TEST(Textures, Deterministic) {
  BarkLook bark;
  Rng a(1, "bark"), b(1, "bark"), c(2, "bark");
  const Rgba8 x = make_bark_texture(bark, 64, a);
  EXPECT_EQ(x.pixels, make_bark_texture(bark, 64, b).pixels);
  EXPECT_NE(x.pixels, make_bark_texture(bark, 64, c).pixels);
}

// Every bark style tiles: across the wrap (last column -> first) the image changes no more than
// between neighbouring interior columns, in u and in v.
TEST(Textures, BarkTiles) {
  for (BarkStyle style : {BarkStyle::kFissured, BarkStyle::kSmooth, BarkStyle::kBirch, BarkStyle::kScaly}) {
    BarkLook look;
    look.style = style;
    Rng rng(3, "bark");
    const Rgba8 img = make_bark_texture(look, 128, rng);
    double interior_u = 0, interior_v = 0;
    for (int i = 0; i + 1 < 128; ++i) {
      interior_u += line_diff(img, i, i + 1, true) / 127;
      interior_v += line_diff(img, i, i + 1, false) / 127;
    }
    EXPECT_LE(line_diff(img, 127, 0, true), 2.5 * interior_u + 1) << static_cast<int>(style);
    EXPECT_LE(line_diff(img, 127, 0, false), 2.5 * interior_v + 1) << static_cast<int>(style);
    for (std::size_t i = 3; i < img.pixels.size(); i += 4) ASSERT_EQ(img.pixels[i], 255);  // opaque
  }
}

// The atlas has four leaves, one per quadrant: transparent corners and margins, an opaque blade
// in the middle, and the petiole reaching the top edge of its quadrant (low v) in the middle.
TEST(Textures, LeafAtlasSilhouettes) {
  for (LeafShape shape : {LeafShape::kLobed, LeafShape::kOvate, LeafShape::kPalmate, LeafShape::kSpiny,
                          LeafShape::kLanceolate, LeafShape::kNeedle}) {
    LeafLook look;
    look.shape = shape;
    Rng rng(1, "leaves");
    const int size = 256, q = 128;
    const Rgba8 img = make_leaf_atlas(look, size, rng);
    ASSERT_EQ(img.width, size);
    for (int v = 0; v < 4; ++v) {
      const int ox = (v % 2) * q, oy = (v / 2) * q;
      const std::string where =
          "shape " + std::to_string(static_cast<int>(shape)) + " variant " + std::to_string(v);
      EXPECT_EQ(channel(img, ox, oy, 3), 0) << where;  // corners
      EXPECT_EQ(channel(img, ox + q - 1, oy + q - 1, 3), 0) << where;
      EXPECT_EQ(channel(img, ox + q / 2, oy + q - 1, 3), 0) << where;    // beyond the tip
      EXPECT_EQ(channel(img, ox + 2, oy + q / 2, 3), 0) << where;        // side margin
      EXPECT_EQ(channel(img, ox + q / 2, oy + q / 2, 3), 255) << where;  // blade centre
      EXPECT_GT(channel(img, ox + q / 2, oy + 6, 3), 128) << where;      // petiole near the top
      EXPECT_EQ(channel(img, ox + q / 2 - 12, oy + 6, 3), 0) << where;   // ... and thin
    }
  }
}

TEST(Textures, RejectsBadSize) {
  Rng rng(1, "x");
  EXPECT_THROW(make_bark_texture({}, 100, rng), std::invalid_argument);
  EXPECT_THROW(make_leaf_atlas({}, 8, rng), std::invalid_argument);
}

TEST(Textures, SrgbToLinear) {
  const tree::Color c = srgb_to_linear({0.0f, 0.5f, 1.0f});
  EXPECT_FLOAT_EQ(c.r, 0.0f);
  EXPECT_NEAR(c.g, 0.214, 0.001);
  EXPECT_FLOAT_EQ(c.b, 1.0f);
}

}  // namespace
}  // namespace sylva::generate

namespace sylva::generate {
namespace {

// Mip-safe alpha on every species' card atlas: the base level's alpha-test coverage is unchanged
// (the halo stays under the cutoff); drawn as clients draw it (trilinear samples of plain
// box-filtered mipmaps), the coverage at every level of detail down to cells two texels across
// stays within a factor of 2.5 of the base level's, at one texel across above 1/2.5 of it (a card
// there may be drawn almost whole), and past it (a card drawn whole or not) the cards are drawn. Without the
// halo every species' cards vanish (under a tenth of the base coverage) before cells are one texel across:
// far trees lose their leaves.
TEST(MipSafeAlpha, EverySpeciesAtlasKeepsItsCoverage) {
  int vanish_without = 0, species = 0;
  for (const auto& e : std::filesystem::directory_iterator("configs/species")) {
    if (e.path().extension() != ".yaml") continue;
    const SpeciesPreset s = load_species_preset(e.path());
    Rng rng(1, "leaves");
    CardAtlas atlas = make_card_atlas(s.card, s.leaf, s.bark, 256, rng);
    const Rgba8 before = atlas.image;
    const MipSafety m = make_mip_safe(atlas.image, atlas.columns, atlas.rows, 0.5f);
    ++species;
    // 256 px atlas, cells 64 x 128: lods 0 .. 6.5 fitted, 7 .. 8 drawn whole or not.
    ASSERT_EQ(m.lods.size(), 17u) << s.species;
    ASSERT_EQ(m.coverage.size(), m.lods.size()) << s.species;
    std::size_t pass_before = 0, pass_after = 0;
    for (std::size_t i = 3; i < before.pixels.size(); i += 4) {
      pass_before += before.pixels[i] >= 128;
      pass_after += atlas.image.pixels[i] >= 128;
      ASSERT_GE(atlas.image.pixels[i], before.pixels[i]);
    }
    EXPECT_EQ(pass_before, pass_after) << s.species;
    const double c0 = m.coverage[0];
    for (std::size_t l = 1; l < m.lods.size(); ++l) {
      if (m.lods[l] <= 6.5) {
        EXPECT_GT(m.coverage[l], c0 / 2.5) << s.species << " lod " << m.lods[l];
      }
      if (m.lods[l] <= 5.5) {
        EXPECT_LT(m.coverage[l], c0 * 2.5) << s.species << " lod " << m.lods[l];
      } else if (m.lods[l] > 6.5) {
        EXPECT_GE(m.coverage[l], c0) << s.species << " lod " << m.lods[l];
      }
    }
    double least_plain = 1;
    for (std::size_t l = 0; l < m.lods.size() && m.lods[l] <= 6.5; ++l)
      least_plain = std::min(least_plain, m.coverage_plain[l] / m.coverage_plain[0]);
    vanish_without += least_plain < 0.1;
  }
  EXPECT_EQ(species, 8);
  EXPECT_EQ(vanish_without, 8);
}

}  // namespace
}  // namespace sylva::generate
