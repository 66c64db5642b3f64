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

// The alpha channel of the plain mip chain every glTF client builds for a PNG (glGenerateMipmap
// in three.js, Babylon.js, Blender and sylva's renderer): [0] is `base`'s alpha, then each level
// the mean of 2 x 2 texels of the previous (a 1-texel side keeps its size), as stored in 8 bits
// (values k / 255), down to 1 x 1.
struct AlphaLevel {
  int width = 0, height = 0;
  std::vector<float> alpha;  // row-major, in [0, 1]
};
std::vector<AlphaLevel> box_alpha_mips(const Image& base);

// What an alpha test at `cutoff` keeps of a texture drawn at level of detail `lod` (>= 0; 0 =
// one texel per pixel, each +1 halves the texels per pixel): the fraction of texel-centre
// positions, every `step` (>= 1) base texels in x and y, whose alpha sampled as GL's
// LINEAR_MIPMAP_LINEAR does (bilinear in levels floor(lod) and floor(lod) + 1, linear between
// them; REPEAT wrap; lods past the last level use it) is >= cutoff. This is the coverage a
// client's alpha test produces, which texel coverage of the stored levels overestimates: the
// bilinear and between-level blends average a coarse level once more.
double sampled_alpha_coverage(const std::vector<AlphaLevel>& mips, double lod, float cutoff, int step = 1);

}  // namespace sylva::image
