// composite_bake_texel (bake_layers.h): the packed opaque texel alone, lines alone, lines over
// an opaque texel, and uncovered texels.
#include "libs/render/bake_layers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>

namespace sylva::render {
namespace {

using Px = std::array<std::uint16_t, 4>;
using Out = std::array<std::uint8_t, 4>;

// The packed layer's texel as the bake shader writes it.
Px packed(Out rgb_, Out normal_depth) {
  return {std::uint16_t(rgb_[0] | rgb_[1] << 8), std::uint16_t(rgb_[2] | normal_depth[0] << 8),
          std::uint16_t(normal_depth[1] | normal_depth[2] << 8), std::uint16_t(normal_depth[3] | 0xFF00)};
}

// A blended layer's texel: premultiplied value v * a (0..1) in rgb, coverage a.
Px layer(double r, double g, double b, double a) {
  auto u = [](double v) { return std::uint16_t(std::lround(v * 65535)); };
  return {u(r * a), u(g * a), u(b * a), u(a)};
}

struct Result {
  Out color{7, 7, 7, 7}, normal_depth{7, 7, 7, 7};  // 7: untouched
};

Result composite(const Px& opaque, const Px& lc, const Px& ln, const Px& ld) {
  Result r;
  composite_bake_texel(opaque.data(), lc.data(), ln.data(), ld.data(), r.color.data(), r.normal_depth.data());
  return r;
}

const Px kNone{0, 0, 0, 0};

TEST(BakeLayers, AnOpaqueTexelAloneKeepsItsPackedBytes) {
  const Result r = composite(packed({10, 200, 30, 0}, {128, 250, 127, 77}), kNone, kNone, kNone);
  EXPECT_EQ(r.color, (Out{10, 200, 30, 255}));
  EXPECT_EQ(r.normal_depth, (Out{128, 250, 127, 77}));
}

TEST(BakeLayers, AnUncoveredTexelIsLeftAlone) {
  const Result r = composite(kNone, kNone, kNone, kNone);
  EXPECT_EQ(r.color, (Out{7, 7, 7, 7}));
  EXPECT_EQ(r.normal_depth, (Out{7, 7, 7, 7}));
  // Lines covering less than half a level of 8-bit alpha count as uncovered too.
  const Px faint = layer(1, 1, 1, 0.001);
  const Result f = composite(kNone, faint, faint, faint);
  EXPECT_EQ(f.color, (Out{7, 7, 7, 7}));
}

TEST(BakeLayers, LinesAloneAreTheirCompositeDividedByTheirCoverage) {
  // Colour 0.4 (sRGB-encoded), normal (0.2, 0.6, -0.2) encoded 0.6, 0.8, 0.4, depth 0.2,
  // coverage 0.3.
  const Result r =
      composite(kNone, layer(0.4, 0.4, 0.4, 0.3), layer(0.6, 0.8, 0.4, 0.3), layer(0.2, 0, 0, 0.3));
  EXPECT_EQ(r.color, (Out{102, 102, 102, 77}));  // 0.4 * 255, 0.3 * 255
  EXPECT_EQ(r.normal_depth, (Out{153, 204, 102, 51}));
}

TEST(BakeLayers, LinesOverAnOpaqueTexelCompositeAsDrawingThemOverIt) {
  // Opaque: colour 200, normal (0, 0, 1) = 128, 128, 255, depth 100. Lines: colour 0.2, normal
  // (1, 0, 0) = 1, 0.5, 0.5, depth 0.9, coverage 0.25.
  const Result r = composite(packed({200, 200, 200, 0}, {128, 128, 255, 100}), layer(0.2, 0.2, 0.2, 0.25),
                             layer(1, 0.5, 0.5, 0.25), layer(0.9, 0, 0, 0.25));
  const int c = int(std::lround(255 * (0.25 * 0.2 + 0.75 * 200 / 255.0)));
  EXPECT_EQ(r.color, (Out{std::uint8_t(c), std::uint8_t(c), std::uint8_t(c), 255}));
  // The mean normal keeps its length (0.25 (1, 0, 0) + 0.75 (0, 0, 1) is shorter than 1).
  auto enc = [](double v) { return std::uint8_t(std::lround((v * 0.5 + 0.5) * 255)); };
  const double nz = (255 / 255.0) * 2 - 1;
  EXPECT_EQ(r.normal_depth[0], enc(0.25 + 0.75 * (128 / 255.0 * 2 - 1)));
  EXPECT_EQ(r.normal_depth[2], enc(0.75 * nz));
  EXPECT_EQ(r.normal_depth[3], std::uint8_t(std::lround(255 * (0.25 * 0.9 + 0.75 * 100 / 255.0))));
}

TEST(BakeLayers, AMeanNormalLongerThanOneIsShortenedToOne) {
  // Encoded (1, 1, 0.5) over nothing: (1, 1, 0), length sqrt 2, becomes (0.707, 0.707, 0).
  const Result r = composite(kNone, layer(1, 1, 1, 1), layer(1, 1, 0.5, 1), layer(0.5, 0, 0, 1));
  const auto e = std::uint8_t(std::lround((std::sqrt(0.5) * 0.5 + 0.5) * 255));
  EXPECT_EQ(r.normal_depth, (Out{e, e, 128, 128}));
  EXPECT_EQ(r.color[3], 255);
}

}  // namespace
}  // namespace sylva::render
