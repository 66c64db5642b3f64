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

// The same texels as two convex polygons, one above the other (sharing at most a row boundary):
// `upper` of at most max_vertices, `lower` of at most lower_vertices, split at the row boundary
// that gives the least total area, or one polygon (`lower` empty) when no split is smaller. A
// tree's crown is wide and its trunk narrow: one convex polygon around both holds wide empty
// wedges beside the trunk down to the ground, and k-vertex reduction puts fictitious corners
// there, metres from the trunk at ground level. A card seen nearly edge-on (the fallback cross's
// other plane in a front view) is a sliver sampled at its coarsest mip level, whose mean colour
// and coverage then fill the whole polygon; in perspective its ground corners, nearer to the
// viewer than the trunk, project below the foot: a stray line below the tree. With the split
// the lower polygon hugs the trunk, so the sliver reaches only where the tree itself reaches (a
// polygon's points project onto the rows its texels' real points project onto, for a viewer in
// its plane). Every reduction vertex stays inside its piece's rows, so the pieces never overlap.
struct SplitCutout {
  std::vector<std::array<double, 2>> upper, lower;  // frame uv as CutoutResult::polygon; lower may be empty
  double area_fraction = 1;                         // both polygons' area / frame area
};
SplitCutout fit_split_cutout(const image::Image& color, const PixelRect& rect, int max_vertices,
                             int lower_vertices = 4, int alpha_threshold = 0);

}  // namespace sylva::impostor
