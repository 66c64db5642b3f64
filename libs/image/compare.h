// Reference-image comparison for render regression tests, on OpenImageIO's
// ImageBufAlgo::compare (the engine behind `idiff`), with the thresholds Blender's render tests
// use by default: a pixel fails when any channel differs by more than 0.016 (about 4 of 255
// levels), and an image fails when more than 1 % of its pixels fail.
//
// Thin high-contrast edges. A twig one pixel wide that moves by a fraction of a pixel between
// two drivers changes the pixels along its edges by up to the full contrast, so those pixels
// fail the per-pixel test no matter how the threshold is set. The failing-pixel *fraction* is
// what absorbs them: edges are a small share of a frame, and verification renders use 4x MSAA,
// which turns a one-pixel jump into coverage steps of 1/4, so a subpixel shift changes far fewer
// pixels, and by less, than aliased rendering would. A structural change (a missing branch, a
// shifted object, a wrong texture) fails many pixels at once and is caught. Scenes dominated by
// sub-pixel geometry (a distant forest) may need a larger allowed fraction; raise it per recipe
// rather than raising the per-pixel threshold, which would hide colour and lighting changes.
#pragma once

#include <cstddef>
#include <string>

#include "libs/image/image.h"

namespace sylva::image {

struct CompareOptions {
  // Per-channel absolute difference, in units of full scale (1.0 = 255 levels), above which a
  // pixel counts as failing. Blender / idiff: -fail 0.016.
  double pixel_threshold = 0.016;
  // The image passes while failing_pixels <= max_failing_fraction * pixels.
  // Blender / idiff: -failpercent 1.
  double max_failing_fraction = 0.01;
  // Compare the alpha channel too (false: RGB only). Renders over an opaque background have
  // alpha 255 everywhere, so this only matters for images with transparency (impostors).
  bool compare_alpha = true;
};

struct CompareResult {
  bool passed = false;
  // Empty when passed; otherwise one sentence saying why, e.g.
  //   "2.40% of pixels differ by more than 0.016 (allowed 1.00%)"
  //   "size mismatch: reference 512x512, test 256x256"
  std::string failure;
  bool size_mismatch = false;

  std::size_t pixels = 0;          // pixels compared (0 on size mismatch)
  std::size_t failing_pixels = 0;  // pixels with some channel difference > pixel_threshold
  double failing_fraction = 0;     // failing_pixels / pixels
  // Per-channel absolute differences in full-scale units (0..1), over all compared channels.
  double mean_error = 0;
  double rms_error = 0;
  double max_error = 0;
  int max_x = 0, max_y = 0;  // where max_error occurs (top-left origin)
  // Peak signal-to-noise ratio in dB, 20*log10(1/rms_error); +infinity for identical images
  // (callers writing JSON should map it to null or a large number).
  double psnr = 0;
};

// Compares `test` against `ref`. Never throws; images of different sizes give a failed result
// with size_mismatch set. The numbers are computed single-threaded so they are reproducible to
// the last bit.
CompareResult compare_images(const Image& ref, const Image& test, const CompareOptions& options = {});

// A picture of where the images differ, the size of the larger of the two:
//  - identical pixels: the reference, in dimmed grey (for orientation);
//  - differences within the threshold: dark blue, brighter as the difference grows;
//  - failing pixels: a heat ramp red -> yellow -> white as the difference grows from the
//    threshold to 0.5 of full scale and beyond;
//  - pixels that exist in only one image (size mismatch): magenta.
// Opaque (alpha 255) everywhere.
Image diff_heatmap(const Image& ref, const Image& test, const CompareOptions& options = {});

}  // namespace sylva::image
