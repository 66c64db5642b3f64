// OpenImageIO reads every format it knows; PNG writing is libpng's (png.cpp).
#include "libs/image/image_io.h"

#include <OpenImageIO/imageio.h>

#include <system_error>

namespace sylva::image {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& why) {
  throw ImageError(path.string() + ": error: " + why);
}

std::string oiio_message(const std::string& s) {
  // OIIO messages may span several lines; keep the report to one.
  std::string out;
  for (char c : s) out += (c == '\n' ? ' ' : c);
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out.empty() ? std::string("unknown OpenImageIO error") : out;
}

}  // namespace

Image read_image(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "no such image file");
  // Keep alpha straight: by default OIIO premultiplies PNG colour by alpha on read.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) fail(path, "cannot read image: " + oiio_message(OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  const int w = spec.width, h = spec.height, nch = spec.nchannels;
  if (w <= 0 || h <= 0 || nch <= 0) fail(path, "image has no pixels");
  // Map the channels to RGBA; a second channel of a two-channel image is alpha.
  const int alpha = spec.alpha_channel >= 0 ? spec.alpha_channel : (nch == 2 ? 1 : (nch >= 4 ? 3 : -1));
  Image img(w, h);
  auto& out = img.bytes();
  if (nch == 4 && alpha == 3) {  // RGBA already: decode straight into the image
    if (!in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, out.data()))
      fail(path, "cannot decode image: " + oiio_message(in->geterror()));
    in->close();
    return img;
  }
  std::vector<std::uint8_t> raw(std::size_t(w) * std::size_t(h) * std::size_t(nch));
  if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, raw.data()))
    fail(path, "cannot decode image: " + oiio_message(in->geterror()));
  in->close();
  for (std::size_t i = 0; i < img.pixel_count(); ++i) {
    const std::uint8_t* p = &raw[i * std::size_t(nch)];
    std::uint8_t* q = &out[i * 4];
    if (nch <= 2) {
      q[0] = q[1] = q[2] = p[0];
    } else {
      q[0] = p[0];
      q[1] = p[1];
      q[2] = p[2];
    }
    q[3] = alpha >= 0 ? p[alpha] : 255;
  }
  return img;
}

}  // namespace sylva::image
