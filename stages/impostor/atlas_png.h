// The atlas maps as PNG files: both encoded side by side (oneTBB), at the stage's zlib level.
//
// Level 3: the two 4096^2 maps encode in 56 % of level 6's CPU time for 6 % more bytes
// (docs/performance.md, BM_EncodeMaps). The two encodes are independent, so running them in
// parallel changes no byte (encode_png is deterministic).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "libs/image/image.h"

namespace sylva::impostor {

constexpr int kAtlasPngLevel = 3;

struct AtlasPngs {
  std::vector<std::uint8_t> color, normal_depth;
};

// image::encode_png of each map at kAtlasPngLevel. Throws image::ImageError.
AtlasPngs encode_atlas_pngs(const image::Image& color, const image::Image& normal_depth);

}  // namespace sylva::impostor
