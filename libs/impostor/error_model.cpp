// The impostor's error terms (error_model.h says what each bounds); the model itself is
// libs/lodmodel (docs/lod-model.md).
#include "libs/impostor/error_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sylva::impostor {

double switch_distance(const lodmodel::Camera& camera, const ErrorTerms& terms, double delta) {
  return lodmodel::switch_distance(camera, terms.epsilon_m(), delta);
}

double billboard_max_view_angle(int cards, bool top_card) {
  // For a view at elevation e, halfway in azimuth between two vertical cards (the worst azimuth),
  // the nearest vertical card's normal is acos(cos e cos(pi/K)) away and the top card's 90° - e.
  // The worst elevation is where the smaller of the two is largest: scan it finely.
  const double half_step = std::numbers::pi / std::max(1, cards);
  double worst = 0;
  for (int s = 0; s <= 9000; ++s) {
    const double e = (std::numbers::pi / 2) * s / 9000.0;
    double a = std::acos(std::clamp(std::cos(e) * std::cos(half_step), -1.0, 1.0));
    if (top_card) a = std::min(a, std::numbers::pi / 2 - e);
    worst = std::max(worst, a);
  }
  return worst;
}

}  // namespace sylva::impostor
