#include "stages/generate/natural_rules.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace sylva::generate {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

// B.5: C_p^E + C_s^E = 1 (da Vinci) and C_s / C_p = S.
TEST(NaturalRules, RadiusConstantsSatisfyDaVinci) {
  for (double e : {2.0, 2.49, 3.0})
    for (double s : {0.1, 0.45, 1.0}) {
      const RadiusSplit c = radius_constants(e, s);
      EXPECT_NEAR(std::pow(c.primary, e) + std::pow(c.secondary, e), 1.0, 1e-14);
      EXPECT_NEAR(c.secondary / c.primary, s, 1e-14);
    }
}

// Appendix B.1.1's worked numbers: equal split total angle 0° (E=2), 59° (E=2.49), 75° (E=3).
TEST(NaturalRules, EqualSplitTotalAngleMatchesThesis) {
  EXPECT_NEAR(total_angle(2.0, 1.0), 0.0, 1e-7);
  EXPECT_NEAR(total_angle(2.49, 1.0) / kDeg, 59.0, 0.5);
  EXPECT_NEAR(total_angle(3.0, 1.0) / kDeg, 75.0, 0.5);
  EXPECT_NEAR(clone_deviation(2.49, 2), total_angle(2.49, 1.0) / 2, 1e-15);
}

// Murray's per-branch angles sum to the B.2/B.3 total, and reproduce the check in the seed notes
// (E=2.49, S=0.5: primary 11.1°, secondary 50.4°).
TEST(NaturalRules, MurrayPerBranchAngles) {
  const MurrayAngles m = murray_angles_for_ratio(2.49, 0.5);
  EXPECT_NEAR(m.primary / kDeg, 11.1, 0.1);
  EXPECT_NEAR(m.secondary / kDeg, 50.4, 0.1);
  for (double s : {0.2, 0.5, 0.8, 1.0})
    EXPECT_NEAR(m.primary + m.secondary + 0 * s, total_angle(2.49, 0.5), 1e-9);
  for (double s : {0.2, 0.5, 0.8, 1.0}) {
    const MurrayAngles a = murray_angles_for_ratio(2.7, s);
    EXPECT_NEAR(a.primary + a.secondary, total_angle(2.7, s), 1e-9) << s;
    EXPECT_LE(a.primary, a.secondary + 1e-12) << "the thicker child deviates less";
  }
  // Equal children: x = y.
  const MurrayAngles eq = murray_angles_for_ratio(3.0, 1.0);
  EXPECT_NEAR(eq.primary, eq.secondary, 1e-12);
}

// As S -> 0 the total approaches 90° (B.1.2): the primary never bends backwards.
TEST(NaturalRules, ThinChildApproachesRightAngle) {
  EXPECT_NEAR(total_angle(2.49, 1e-4) / kDeg, 90.0, 1.0);
  EXPECT_GT(total_angle(2.49, 1e-4), total_angle(2.49, 1e-2));
}

TEST(NaturalRules, CloneRadius) {
  EXPECT_NEAR(std::pow(clone_radius_factor(2.49, 3), 2.49) * 3, 1.0, 1e-14);  // B.7
  EXPECT_DOUBLE_EQ(child_offset(0.5, 2.0), 3.0);                              // eq. 3.5
}

}  // namespace
}  // namespace sylva::generate
