// PNG encoding and decoding with libpng directly: the light half of libs/image, linked by the
// `sylva` binary itself (stages that write textures), so plain PNG I/O never loads
// OpenImageIO (docs/architecture.md, "Heavy libraries load lazily").
//
// encode_png() is deterministic: the same Image always gives the same bytes (zlib level 6 with
// the default strategy, libpng's adaptive filtering, no timestamp or text chunks). It writes the same chunks
// OpenImageIO 2.4's PNG writer wrote before (IHDR, oFFs 0/0, IDAT, IEND), so files written by
// earlier versions of sylva are byte-identical to today's. write_png() is atomic (temporary
// sibling, then rename), so a crash never leaves a half-written PNG behind.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "libs/image/image.h"

namespace sylva::image {

// Every I/O failure. what() is one line: "<path>: error: <reason>".
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The PNG file bytes of `img` (RGBA, 8 bits per channel). Throws ImageError if it is empty.
std::vector<std::uint8_t> encode_png(const Image& img);

// Encoder settings; the defaults are encode_png(img)'s. Every setting stays deterministic.
struct PngOptions {
  int zlib_level = 6;  // 0 (stored) .. 9 (smallest); lower is faster and larger
};
// As encode_png(img) with `options`; also throws ImageError for a zlib level outside 0..9.
std::vector<std::uint8_t> encode_png(const Image& img, const PngOptions& options);

// Decodes PNG bytes (any PNG colour type and bit depth) to 8-bit RGBA: grey is replicated to
// RGB, a missing alpha channel becomes 255, 16-bit samples keep their high byte, palettes are
// expanded. `name` only labels errors. Throws ImageError ("<name>: error: <reason>").
Image decode_png(std::string_view bytes, const std::string& name = "<png>");

// Reads and decodes a PNG file. Throws ImageError naming the file.
Image read_png(const std::filesystem::path& path);

// Writes encode_png(img) to `path` atomically; creates no directories. Throws ImageError.
void write_png(const Image& img, const std::filesystem::path& path);
void write_png(const Image& img, const std::filesystem::path& path, const PngOptions& options);

}  // namespace sylva::image
