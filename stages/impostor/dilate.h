// Dilation of an atlas's colour into the texels nothing covers, frame by frame.
//
// Texture filtering and mip generation average a texel's RGB with its neighbours' regardless of
// their alpha. Transparent texels left black darken every edge of the tree as soon as it is
// filtered (the dark fringe of alpha-tested foliage). So every texel of a frame with alpha 0
// within `band` texels of a covered one (8-connected breadth-first distance) takes the colour and
// the normal of the nearest covered texel of the same frame, ties broken by scan order; its alpha
// stays 0. A band of 2^mip_levels texels is what bilinear sampling up to that mip level can reach
// from a covered texel (docs/stages/impostor.md, "Padding and dilation"); farther texels stay
// black, which keeps the PNGs small. Depth is not dilated: an uncovered texel's depth is 0, the
// back of the bounding sphere, so a ray the shader marches through the depth map passes through
// empty space to whatever lies behind it. Deterministic; O(texels); frames are dilated in
// parallel (oneTBB), which changes no byte.
#pragma once

#include <vector>

#include "libs/image/image.h"

namespace sylva::impostor {

struct PixelRect {
  int x = 0, y = 0, w = 0, h = 0;
};

// `color` and `normal_depth` have the same size; rects lie inside and do not overlap (else
// std::invalid_argument). Alpha of `color` decides what is covered. band >= 1.
void dilate_frames(image::Image& color, image::Image& normal_depth, const std::vector<PixelRect>& rects,
                   int band);

}  // namespace sylva::impostor
