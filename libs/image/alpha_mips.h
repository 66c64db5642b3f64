// Mipmaps for alpha-tested textures that keep the alpha test's coverage on every level.
//
// Seed: Ignacio Castaño, "Computing Alpha Mipmaps" (2010) — the "alpha to coverage preserving"
// mipmaps: box filtering makes alpha-tested foliage thinner and thinner with distance (a texel of
// a coarse level averages leaf and gap, falls under the cutoff and is discarded). Castaño scales
// each level's alpha so that the fraction of texels passing the test equals the base level's.
//
// Colour is averaged in linear light weighted by alpha (the bytes are sRGB, alpha straight), so
// transparent texels do not darken the edges. Pure: no GL, no I/O; deterministic.
#pragma once

#include <vector>

#include "libs/image/image.h"

namespace sylva::image {

// Fraction of texels whose alpha is >= cutoff (alpha in [0, 1], cutoff in (0, 1]).
double alpha_coverage(const Image& img, float cutoff);

// The full chain: [0] is `base`, then each level half the previous one's size (floored, at least
// 1) down to 1 x 1; every level's alpha scaled (clamped to 1) so that its alpha_coverage at
// `cutoff` is as close as 8-bit alpha allows to the base level's. cutoff <= 0: plain box-filtered
// mips (the comparison the tests make).
std::vector<Image> coverage_preserving_mips(const Image& base, float cutoff);

}  // namespace sylva::image
