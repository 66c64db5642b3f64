// Reading and writing images with OpenImageIO.
//
// write_png() is deterministic: the same Image always gives the same file bytes (fixed zlib
// level, no timestamps, no software/version tags), and the file appears atomically (written to
// a temporary sibling, then renamed), so a crash never leaves a half-written PNG behind.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/image/image.h"

namespace sylva::image {

// Every I/O failure. what() is one line: "<path>: error: <reason>".
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads any format OpenImageIO knows (PNG, JPEG, TIFF, EXR, ...), first subimage, converted to
// 8-bit RGBA: grey is replicated to RGB, a missing alpha channel becomes 255, extra channels are
// dropped, wider types are rounded to 8 bits (no colour-space conversion is applied).
// Throws ImageError naming the file when it cannot be opened or decoded.
Image read_image(const std::filesystem::path& path);

// The PNG file bytes of `img` (RGBA, 8 bits per channel, no metadata chunks besides what the
// format requires). Throws ImageError if the image is empty.
std::vector<std::uint8_t> encode_png(const Image& img);

// Writes encode_png(img) to `path` atomically; creates no directories. Throws ImageError.
void write_png(const Image& img, const std::filesystem::path& path);

}  // namespace sylva::image
