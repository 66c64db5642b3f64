// The impostor's place in the LOD error model (docs/lod-model.md; libs/lodmodel computes it): its
// spatial error epsilon in metres, and the switch distance d = epsilon / (delta s(1)) from which it
// stays within delta pixels, s(d) = 2 d tan(phi/2) / H.
//
// An impostor misplaces a point of the tree by at most the sum of three terms (they are
// displacements of the same edge by independent causes, so they add, as Zhang's E1 + E2 do):
//   - source:  the epsilon of the LOD level it was baked from (0 for a mesh);
//   - texel:   one atlas texel, t = 2 W / F (W the frame's half extent in metres, F the frame
//              size in texels): the atlas samples the tree at pitch t, so an edge is known to
//              within one texel (the "one atlas texel under the pixel budget");
//   - view:    the view interpolation. Octahedral kinds reproject each of the three blended frames
//              with its depth map (the shader's parallax step), so a visible point lands where it
//              belongs and the first-order parallax h sin(theta) cancels; what remains is the
//              second-order error of an outline, R (1 - cos theta) for a convex part of radius R
//              (Pasman 2001, "image with depth"), weighted by the blend: R * view_error_factor().
//              Billboards are flat cards without depth: a point at distance h from a card plane
//              moves by h sin(theta), theta the angle between the view and the nearest card's
//              normal, so view = R sin(theta_max) (first order).
// Disocclusion (what one frame cannot see) is not bounded by this model; `sylva impostorcheck`
// measures it (docs/stages/impostor.md).
#pragma once

#include "libs/lodmodel/lod_model.h"

namespace sylva::impostor {

struct ErrorTerms {
  double source_m = 0;  // epsilon of the baked LOD level (0 for a full mesh)
  double texel_m = 0;   // one atlas texel
  double view_m = 0;    // view interpolation (see the header comment)
  double epsilon_m() const { return source_m + texel_m + view_m; }
  friend bool operator==(const ErrorTerms&, const ErrorTerms&) = default;
};

// lodmodel::switch_distance for epsilon = terms.epsilon_m() (delta > 0, px).
double switch_distance(const lodmodel::Camera& camera, const ErrorTerms& terms, double delta);

// The largest angle between a view direction (elevation 0..90°, any azimuth) and the normal of the
// nearest card of a billboard set: `cards` vertical cards 360/cards degrees apart, plus a
// horizontal card when `top_card`. Radians.
double billboard_max_view_angle(int cards, bool top_card);

}  // namespace sylva::impostor
