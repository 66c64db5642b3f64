// Supersampled renders (lodcheck) integrate sub-pixel twigs and needles instead of sampling
// them at 4 MSAA positions; the average has to be taken in linear light, as coverage is, and
// weighted by alpha (the images hold straight alpha).
#include "libs/image/resample.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <stdexcept>
#include <string>

namespace sylva::image {

Image downsample(const Image& img, int factor) {
  if (factor < 1) throw std::invalid_argument("downsample: factor must be >= 1");
  if (factor == 1) return img;
  if (img.width() % factor != 0 || img.height() % factor != 0)
    throw std::invalid_argument("downsample: " + std::to_string(img.width()) + "x" +
                                std::to_string(img.height()) + " is not a multiple of " +
                                std::to_string(factor));
  const OIIO::ImageSpec spec(img.width(), img.height(), 4, OIIO::TypeDesc::UINT8);
  OIIO::ImageBuf src(spec, const_cast<std::uint8_t*>(img.bytes().data()));
  OIIO::ImageBuf linear(
      OIIO::ImageSpec(img.width(), img.height(), 4, OIIO::TypeDesc::FLOAT));  // no 8-bit linear banding
  OIIO::ImageBufAlgo::colorconvert(linear, src, "sRGB", "linear", /*unpremult=*/false, "", "", nullptr, {},
                                   1);
  // Straight alpha: a pixel's colour counts by its coverage (premultiply, average, divide), or
  // the transparent pixels' black would darken every partly covered pixel of the result.
  OIIO::ImageBuf weighted(OIIO::ImageSpec(img.width(), img.height(), 4, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBufAlgo::premult(weighted, linear, {}, 1);
  const int w = img.width() / factor, h = img.height() / factor;
  OIIO::ImageBuf small(OIIO::ImageSpec(w, h, 4, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBufAlgo::resize(small, weighted, "box", 1.0f, OIIO::ROI(0, w, 0, h, 0, 1, 0, 4), 1);
  OIIO::ImageBuf straight(OIIO::ImageSpec(w, h, 4, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBufAlgo::unpremult(straight, small, {}, 1);
  OIIO::ImageBuf encoded(OIIO::ImageSpec(w, h, 4, OIIO::TypeDesc::FLOAT));
  OIIO::ImageBufAlgo::colorconvert(encoded, straight, "linear", "sRGB", false, "", "", nullptr, {}, 1);
  Image out(w, h);
  if (!encoded.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, 4), OIIO::TypeDesc::UINT8, out.bytes().data()))
    throw std::runtime_error("downsample: " + encoded.geterror());
  return out;
}

}  // namespace sylva::image
