// libpng reports errors through longjmp; every libpng call here happens inside one function
// that owns the setjmp, with no C++ object created after it that needs a destructor, so the
// jump never skips one. Messages are collected in a plain buffer and thrown after the jump.
#include "libs/image/png.h"

#include <png.h>
#include <unistd.h>
#include <zlib.h>

#include <atomic>
#include <csetjmp>
#include <cstring>
#include <fstream>
#include <system_error>

#include "libs/fileio/read_file.h"

namespace sylva::image {
namespace {

struct PngError {
  char message[256] = "";
};

extern "C" void on_png_error(png_structp png, png_const_charp msg) {
  auto* e = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(e->message, sizeof e->message, "%s", msg);
  png_longjmp(png, 1);
}
extern "C" void on_png_warning(png_structp, png_const_charp) {}

struct Sink {
  std::vector<std::uint8_t>* out;
};
extern "C" void on_png_write(png_structp png, png_bytep data, png_size_t n) {
  auto* s = static_cast<Sink*>(png_get_io_ptr(png));
  s->out->insert(s->out->end(), data, data + n);
}
extern "C" void on_png_flush(png_structp) {}

struct Source {
  const unsigned char* data;
  std::size_t size, at;
};
extern "C" void on_png_read(png_structp png, png_bytep data, png_size_t n) {
  auto* s = static_cast<Source*>(png_get_io_ptr(png));
  if (s->size - s->at < n) png_error(png, "file is truncated");
  std::memcpy(data, s->data + s->at, n);
  s->at += n;
}

// Returns false (and sets err) on a libpng error; `rows` must stay alive meanwhile.
bool encode(const Image& img, const PngOptions& o, std::vector<std::uint8_t>& out,
            std::vector<png_bytep>& rows, PngError& err) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, on_png_error, on_png_warning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  Sink sink{&out};
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, info ? &info : nullptr);
    return false;
  }
  png_set_write_fn(png, &sink, on_png_write, on_png_flush);
  png_set_compression_level(png, o.zlib_level);
  // OpenImageIO's choice (libpng would pick Z_FILTERED for filtered rows): same bytes as before.
  png_set_compression_strategy(png, Z_DEFAULT_STRATEGY);
  png_set_IHDR(png, info, static_cast<png_uint_32>(img.width()), static_cast<png_uint_32>(img.height()), 8,
               PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  // The oFFs chunk OpenImageIO always wrote (origin 0, 0): kept so PNG bytes did not change
  // when sylva moved from OpenImageIO to libpng for PNG files.
  png_set_oFFs(png, info, 0, 0, PNG_OFFSET_PIXEL);
  png_write_info(png, info);
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

struct Decoded {
  png_uint_32 width = 0, height = 0;
};

bool decode(Source& src, std::vector<std::uint8_t>& rgba, Decoded& d, PngError& err) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &err, on_png_error, on_png_warning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  std::vector<png_bytep> rows;
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    return false;
  }
  png_set_read_fn(png, &src, on_png_read);
  png_read_info(png, info);
  d.width = png_get_image_width(png, info);
  d.height = png_get_image_height(png, info);
  if (d.width == 0 || d.height == 0 || d.width > 65536 || d.height > 65536)
    png_error(png, "image size is out of range");
  const int type = png_get_color_type(png, info);
  if (png_get_bit_depth(png, info) == 16) png_set_strip_16(png);
  if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (type == PNG_COLOR_TYPE_GRAY && png_get_bit_depth(png, info) < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
  if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
  png_set_filler(png, 0xff, PNG_FILLER_AFTER);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  if (png_get_rowbytes(png, info) != std::size_t(d.width) * 4) png_error(png, "unsupported PNG layout");
  rgba.resize(std::size_t(d.width) * std::size_t(d.height) * 4);
  rows.resize(d.height);
  for (png_uint_32 y = 0; y < d.height; ++y)
    rows[y] = rgba.data() + std::size_t(y) * std::size_t(d.width) * 4;
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

[[noreturn]] void fail(const std::string& name, const std::string& why) {
  throw ImageError(name + ": error: " + why);
}

}  // namespace

std::vector<std::uint8_t> encode_png(const Image& img) { return encode_png(img, PngOptions{}); }

std::vector<std::uint8_t> encode_png(const Image& img, const PngOptions& options) {
  if (options.zlib_level < 0 || options.zlib_level > 9) fail("<png>", "zlib level must be in 0..9");
  if (img.empty()) fail("<png>", "cannot encode an empty image");
  std::vector<png_bytep> rows(static_cast<std::size_t>(img.height()));
  auto* base = const_cast<std::uint8_t*>(img.bytes().data());
  for (int y = 0; y < img.height(); ++y)
    rows[std::size_t(y)] = base + std::size_t(y) * std::size_t(img.width()) * 4;
  std::vector<std::uint8_t> out;
  PngError err;
  if (!encode(img, options, out, rows, err)) fail("<png>", std::string("cannot encode PNG: ") + err.message);
  return out;
}

Image decode_png(std::string_view bytes, const std::string& name) {
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0)
    fail(name, "cannot read image: not a PNG file");
  Source src{reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), 0};
  std::vector<std::uint8_t> rgba;
  Decoded d;
  PngError err;
  if (!decode(src, rgba, d, err)) fail(name, std::string("cannot decode image: ") + err.message);
  Image img(static_cast<int>(d.width), static_cast<int>(d.height));
  img.bytes() = std::move(rgba);
  return img;
}

Image read_png(const std::filesystem::path& path) {
  std::string why;
  auto bytes = fileio::read_regular_file(path, &why);
  if (!bytes) fail(path.string(), why);
  return decode_png(*bytes, path.string());
}

void write_png(const Image& img, const std::filesystem::path& path) { write_png(img, path, PngOptions{}); }

void write_png(const Image& img, const std::filesystem::path& path, const PngOptions& options) {
  std::vector<std::uint8_t> bytes;
  try {
    bytes = encode_png(img, options);
  } catch (const ImageError& e) {
    const std::string msg = e.what();
    fail(path.string(), msg.substr(msg.find("error: ") + 7));
  }
  // Unique per thread and process: two threads writing the same name never share a temp file.
  static std::atomic<unsigned long> counter{0};
  std::filesystem::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) fail(path.string(), "cannot open for writing");
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    f.close();
    if (!f) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      fail(path.string(), "write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    fail(path.string(), "cannot rename temporary file into place");
  }
}

}  // namespace sylva::image
