// Crown opacity (issue 9, "Measures"): how much of its own outline a crown covers, measured on a
// side view. Pure: an image in, a number out.
//
// Definition (issue 9): render the tree from the side (elevation 0, 512 px, fov 40°, the tree
// filling the frame) on a transparent background; a pixel is covered when its alpha is at least
// 128. The tree's width is the span of the covered columns over the whole image. Over the rows
// of the crown — rows whose covered span (first to last covered pixel, inclusive) is wider than
// 25 % of the tree's width — average the fraction of covered pixels within that span. The trunk
// rows (narrow) and empty rows do not count. Returns 0 when no row qualifies.
#pragma once

#include "libs/image/image.h"

namespace sylva::mesh {

struct CrownOpacity {
  double opacity = 0;  // mean covered fraction over the crown rows, in [0, 1]
  int crown_rows = 0;  // rows that counted
  int tree_width = 0;  // covered columns' span (pixels)
};

CrownOpacity crown_opacity(const image::Image& side_view);

}  // namespace sylva::mesh
