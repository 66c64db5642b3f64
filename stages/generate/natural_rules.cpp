// Nystad 2010 §3.1 and Appendix B; Murray 1926/1927 per-branch angles (see natural_rules.h).
#include "stages/generate/natural_rules.h"

#include <algorithm>
#include <cmath>

namespace sylva::generate {

namespace {
double safe_acos(double c) { return std::acos(std::clamp(c, -1.0, 1.0)); }
}  // namespace

RadiusSplit radius_constants(double e, double s) {
  const double k = std::pow(1 + std::pow(s, e), -1 / e);  // B.5
  return {k, s * k};
}

MurrayAngles murray_angles(double r0, double r1, double r2) {
  const double a0 = r0 * r0, a1 = r1 * r1, a2 = r2 * r2;
  const double q0 = a0 * a0, q1 = a1 * a1, q2 = a2 * a2;
  return {safe_acos((q0 + q1 - q2) / (2 * a0 * a1)), safe_acos((q0 + q2 - q1) / (2 * a0 * a2))};
}

MurrayAngles murray_angles_for_ratio(double e, double s) {
  const RadiusSplit c = radius_constants(e, s);
  return murray_angles(1.0, c.primary, c.secondary);
}

double total_angle(double e, double s) {
  return safe_acos((std::pow(1 + std::pow(s, e), 4 / e) - 1 - std::pow(s, 4)) / (2 * s * s));  // B.3
}

double clone_radius_factor(double e, int n) { return std::pow(static_cast<double>(n), -1 / e); }

double clone_deviation(double e, int n) { return total_angle(e, 1.0) / n; }

}  // namespace sylva::generate
