// Integer-factor reduction of a rendering (supersampling): each output pixel is the box average
// of factor x factor input pixels, averaged in linear light (the sRGB-encoded colour is decoded
// first and encoded again after) and weighted by alpha (straight alpha in, straight alpha out),
// through OpenImageIO's ImageBufAlgo::resize with a box filter one output pixel wide.
// Deterministic: single-threaded.
#pragma once

#include "libs/image/image.h"

namespace sylva::image {

// `img` reduced by `factor` (>= 1; 1 returns a copy). The width and height must be multiples of
// `factor`; otherwise throws std::invalid_argument.
Image downsample(const Image& img, int factor);

}  // namespace sylva::image
