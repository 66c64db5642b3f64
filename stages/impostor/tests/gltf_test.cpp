// impostor.glb's pieces (impostor_gltf.h): a vertical card is cut at its centre's vertical into
// two halves that together are the cutout (two triangles more); the top card stays whole.
#include <gtest/gtest.h>

#include <cmath>

#include "stages/impostor/impostor_gltf.h"

namespace sylva::impostor {
namespace {

using P = std::array<double, 2>;

double signed_area(const std::vector<P>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
    a += p[i][0] * p[(i + 1) % p.size()][1] - p[(i + 1) % p.size()][0] * p[i][1];
  return 0.5 * a;
}

Card octagon(const Vec3d& dir) {
  Card c;
  c.dir = dir;
  for (int k = 0; k < 8; ++k) {
    const double a = -2 * 3.14159265358979 * (k + 0.3) / 8;  // clockwise in (u, v): ccw with y up
    c.cutout.push_back({0.5 + 0.4 * std::cos(a), 0.5 + 0.3 * std::sin(a)});
  }
  return c;
}

TEST(ImpostorGlb, AVerticalCardIsCutIntoTwoHalvesAtItsCentre) {
  const Card c = octagon({0, 0, 1});
  const auto pieces = card_pieces(c);
  ASSERT_EQ(pieces.size(), 2u);
  for (const P& q : pieces[0]) EXPECT_LE(q[0], 0.5 + 1e-12);
  for (const P& q : pieces[1]) EXPECT_GE(q[0], 0.5 - 1e-12);
  EXPECT_NEAR(signed_area(pieces[0]) + signed_area(pieces[1]), signed_area(c.cutout), 1e-12);
  EXPECT_GT(signed_area(pieces[0]) * signed_area(c.cutout), 0);
  EXPECT_GT(signed_area(pieces[1]) * signed_area(c.cutout), 0);
  EXPECT_EQ(pieces[0].size() + pieces[1].size() - 4, c.cutout.size());  // two cut vertices in both
  GlbCard g;
  g.card = c;
  EXPECT_EQ(card_triangles({g}), 8u);
}

TEST(ImpostorGlb, TheTopCardAndACardBesideTheAxisStayWhole) {
  const Card top = octagon({0, 1, 0});
  ASSERT_EQ(card_pieces(top).size(), 1u);
  EXPECT_EQ(card_pieces(top)[0], top.cutout);
  Card side = octagon({1, 0, 0});
  for (P& q : side.cutout) q[0] = 0.55 + 0.4 * (q[0] - 0.1);  // entirely right of u = 1/2
  ASSERT_EQ(card_pieces(side).size(), 1u);
  EXPECT_EQ(card_pieces(side)[0], side.cutout);
}

}  // namespace
}  // namespace sylva::impostor
