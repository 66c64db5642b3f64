#include "libs/image/compare.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace sylva::image {
namespace {

// Wraps the pixels without copying; OIIO only reads them.
OIIO::ImageBuf wrap(const Image& img) {
  OIIO::ImageSpec spec(img.width(), img.height(), 4, OIIO::TypeDesc::UINT8);
  return OIIO::ImageBuf(spec, const_cast<std::uint8_t*>(img.bytes().data()));
}

std::string percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f%%", fraction * 100.0);
  return buf;
}

// Largest per-channel difference of a pixel, in full-scale units.
double pixel_error(const std::uint8_t* a, const std::uint8_t* b, int channels) {
  int m = 0;
  for (int c = 0; c < channels; ++c) m = std::max(m, std::abs(int(a[c]) - int(b[c])));
  return m / 255.0;
}

}  // namespace

CompareResult compare_images(const Image& ref, const Image& test, const CompareOptions& options) {
  CompareResult r;
  if (ref.width() != test.width() || ref.height() != test.height() || ref.empty()) {
    r.size_mismatch = true;
    r.failure = "size mismatch: reference " + std::to_string(ref.width()) + "x" +
                std::to_string(ref.height()) + ", test " + std::to_string(test.width()) + "x" +
                std::to_string(test.height());
    r.max_error = 1.0;
    r.failing_fraction = 1.0;
    return r;
  }
  const OIIO::ImageBuf a = wrap(ref), b = wrap(test);
  OIIO::ROI roi = a.roi();
  roi.chend = options.compare_alpha ? 4 : 3;
  const float thresh = float(options.pixel_threshold);
  const OIIO::ImageBufAlgo::CompareResults cr =
      OIIO::ImageBufAlgo::compare(a, b, thresh, thresh, roi, /*nthreads=*/1);

  r.pixels = ref.pixel_count();
  r.failing_pixels = std::size_t(cr.nfail);
  r.failing_fraction = double(r.failing_pixels) / double(r.pixels);
  r.mean_error = cr.meanerror;
  r.rms_error = cr.rms_error;
  r.max_error = cr.maxerror;
  r.max_x = cr.maxx;
  r.max_y = cr.maxy;
  r.psnr = cr.rms_error > 0 ? 20.0 * std::log10(1.0 / cr.rms_error) : std::numeric_limits<double>::infinity();
  // cr.error only mirrors nfail != 0 for two in-memory UINT8 buffers of equal size.
  r.passed = double(r.failing_pixels) <= options.max_failing_fraction * double(r.pixels);
  if (!r.passed) {
    char thr[32];
    std::snprintf(thr, sizeof thr, "%g", options.pixel_threshold);
    r.failure = percent(r.failing_fraction) + " of pixels differ by more than " + thr + " (allowed " +
                percent(options.max_failing_fraction) + ")";
  }
  return r;
}

Image diff_heatmap(const Image& ref, const Image& test, const CompareOptions& options) {
  const int w = std::max(ref.width(), test.width());
  const int h = std::max(ref.height(), test.height());
  const int channels = options.compare_alpha ? 4 : 3;
  const double thr = options.pixel_threshold;
  Image out(w, h, {255, 0, 255, 255});
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (x >= ref.width() || y >= ref.height() || x >= test.width() || y >= test.height())
        continue;  // magenta
      const std::size_t ia = (std::size_t(y) * std::size_t(ref.width()) + std::size_t(x)) * 4;
      const std::size_t ib = (std::size_t(y) * std::size_t(test.width()) + std::size_t(x)) * 4;
      const std::uint8_t* pa = &ref.bytes()[ia];
      const std::uint8_t* pb = &test.bytes()[ib];
      const double e = pixel_error(pa, pb, channels);
      Rgba8 c;
      if (e == 0) {
        // Rec. 709 luma of the reference, dimmed to a quarter.
        const double luma = 0.2126 * pa[0] + 0.7152 * pa[1] + 0.0722 * pa[2];
        const auto g = std::uint8_t(std::lround(luma * 0.25));
        c = {g, g, g, 255};
      } else if (e <= thr) {
        const double t = thr > 0 ? e / thr : 1.0;
        c = {0, 0, std::uint8_t(std::lround(96 + 96 * t)), 255};
      } else {
        const double t = std::clamp((e - thr) / std::max(0.5 - thr, 1e-6), 0.0, 1.0);
        if (t < 0.5) {
          c = {255, std::uint8_t(std::lround(255 * t * 2)), 0, 255};
        } else {
          c = {255, 255, std::uint8_t(std::lround(255 * (t - 0.5) * 2)), 255};
        }
      }
      out.set(x, y, c);
    }
  }
  return out;
}

}  // namespace sylva::image
