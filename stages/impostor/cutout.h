// Cutout geometry for a card: the convex polygon of at most k vertices that contains every
// covered texel of its frame, so the card's triangles skip most of the transparent fill.
//
// Source: SpeedTree's billboard cutouts; Persson 2009 ("Humus"), "Particle trimming": the convex
// hull of the texels above an alpha threshold, reduced to k vertices by repeatedly removing the
// hull edge whose removal (extending its two neighbouring edges to their intersection) adds the
// least area. Every step keeps the polygon convex and containing the hull. A removal whose new
// vertex would leave the frame is not allowed; if no allowed removal is left above k vertices,
// the result is the hull's bounding rectangle (4 vertices).
#pragma once

#include <array>
#include <vector>

#include "libs/image/image.h"
#include "stages/impostor/dilate.h"

namespace sylva::impostor {

struct CutoutResult {
  std::vector<std::array<double, 2>> polygon;  // frame uv: (0,0) top-left, (1,1) bottom-right;
                                               // counter-clockwise with v pointing up
  double area_fraction = 1;                    // polygon area / frame area (the fill the card still costs)
};

// Texels of `rect` with alpha > `alpha_threshold` (0..255) are kept. max_vertices in 3..16. A
// frame with nothing above the threshold gets the whole frame.
CutoutResult fit_cutout(const image::Image& color, const PixelRect& rect, int max_vertices,
                        int alpha_threshold = 0);

}  // namespace sylva::impostor
