// Natural branching rules: da Vinci's area rule with Murray's exponent, and Murray's
// minimum-work branching angles.
//
// Seed: Nystad 2010, §3.1 (eq. 3.1–3.5) and Appendix B (B.1–B.7).
//   da Vinci (3.1/B.1):  r_parent^E = Σ r_i^E, E = TreeShapeExponent (2 = area rule, ~2.49 for
//                         large trees, 3 for small ones [Murray 1927]).
//   Radius constants (B.5): C_p = 1 / (1 + S^E)^(1/E),  C_s = S / (1 + S^E)^(1/E),
//                         S = BranchRatio = r_secondary / r_primary in (0, 1].
//   Murray (3.2/B.2):    cos(x + y) = (r0^4 − r1^4 − r2^4) / (2 r1^2 r2^2).
// How the total is divided between the two children: the thesis's angle ratio (eq. 3.3 with
// C_s, B.6 with C_p) is inconsistent and reproduces neither Murray's exact split. We use
// Murray's exact per-branch angles (minimum work, Murray 1926 eq. for a bifurcation):
//   cos x = (r0^4 + r1^4 − r2^4) / (2 r0^2 r1^2),   cos y = (r0^4 + r2^4 − r1^4) / (2 r0^2 r2^2),
// whose sum satisfies 3.2 exactly (docs/stages/generate.md, "Murray angles").
// Higher-degree splits (B.2, B.7): n equal clones of radius r0 / n^(1/E), each deviating by
// ∠total / n where ∠total is the S = 1 total angle (for n = 2 this equals Murray's x = y).
// All angles in radians.
#pragma once

namespace sylva::generate {

struct RadiusSplit {
  double primary;    // C_p: primary child radius / parent radius
  double secondary;  // C_s: secondary child radius / parent radius
};

// C_p and C_s for exponent e > 0 and ratio s in (0, 1].
RadiusSplit radius_constants(double e, double s);

struct MurrayAngles {
  double primary;    // x: deviation of the child with radius r1 from the parent axis
  double secondary;  // y: deviation of the child with radius r2
};

// Murray's minimum-work angles for a parent r0 and children r1 >= r2 (any radii; the cosines
// are clamped to [−1, 1], so children that break da Vinci give 0 or 180° instead of NaN).
MurrayAngles murray_angles(double r0, double r1, double r2);

// The same for a parent of radius 1 and children C_p, C_s from radius_constants(e, s).
MurrayAngles murray_angles_for_ratio(double e, double s);

// Nystad's B.3 total angle x + y from E and S only (used for n-way splits, with S = 1).
double total_angle(double e, double s);

// Radius of each of n equal clones (B.7): r0 / n^(1/E).
double clone_radius_factor(double e, int n);

// Deviation of each of n >= 2 equal clones from the parent axis (B.2): total_angle(e, 1) / n.
double clone_deviation(double e, int n);

// Child offset (eq. 3.5): distance from the parent axis to the child's first cross-section.
inline double child_offset(double s, double r_parent) { return (1 + s) * r_parent; }

}  // namespace sylva::generate
