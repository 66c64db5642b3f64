// Coverage and colour statistics of two renders over the footprint of what they show: the
// numbers the LOD and impostor checks judge (stages/lod/check, stages/impostor/check).
//
// Both images are renders over a transparent background, so a pixel's alpha is the fraction of
// it the subject covers. The footprint is every pixel that either image covers (alpha > 0); the
// statistics are over the footprint, not the frame, because a distant tree is a few percent of
// the frame. A geometry within delta pixels of the reference moves an edge by at most delta,
// which changes a pixel's coverage by at most delta: `pixel_threshold` is that delta.
#pragma once

#include <cstddef>

#include "libs/image/image.h"

namespace sylva::image {

struct FootprintStats {
  std::size_t footprint_pixels = 0;  // covered in either image
  double failing_fraction = 0;       // footprint pixels whose coverage changed by > pixel_threshold
  double coverage_mean_error = 0;    // mean |coverage change|
  double coverage_bias = 0;          // mean signed change (test - ref): > 0 the test covers more
  double colour_mean_error = 0;      // mean per-channel |RGB difference| (0..1)
  // Mean per-channel |RGB difference| of the straight (un-premultiplied) colours, each pixel
  // weighted by the coverage both images share there, min(alpha_ref, alpha_test): how differently
  // what both show is shaded, not where it is (coverage above says that). shade_weight is the
  // sum of the weights (in pixels): 0 when the images share no coverage.
  double shade_mean_error = 0;
  double shade_weight = 0;
};

// Images of equal size (otherwise every number stays 0 and footprint_pixels is 0).
FootprintStats footprint_stats(const Image& ref, const Image& test, double pixel_threshold);

}  // namespace sylva::image
