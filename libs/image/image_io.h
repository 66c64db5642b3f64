// Reading images of any format with OpenImageIO: the heavy half of libs/image (sylva_image_oiio),
// linked only into the graphics module (docs/architecture.md, "Heavy libraries load lazily").
// Plain PNG encoding and decoding are in png.h (libpng, light), included here for convenience.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/image/image.h"
#include "libs/image/png.h"

namespace sylva::image {

// Reads any format OpenImageIO knows (PNG, JPEG, TIFF, EXR, ...), first subimage, converted to
// 8-bit RGBA: grey is replicated to RGB, a missing alpha channel becomes 255, extra channels are
// dropped, wider types are rounded to 8 bits (no colour-space conversion is applied).
// Throws ImageError naming the file when it cannot be opened or decoded.
Image read_image(const std::filesystem::path& path);

}  // namespace sylva::image
