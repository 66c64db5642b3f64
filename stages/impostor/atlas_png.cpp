// The two atlas PNGs encoded in parallel (atlas_png.h says why this changes no byte).
#include "stages/impostor/atlas_png.h"

#include <tbb/parallel_invoke.h>

#include "libs/image/png.h"

namespace sylva::impostor {

namespace {

image::PngOptions options() {
  image::PngOptions o;
  o.zlib_level = kAtlasPngLevel;
  return o;
}

}  // namespace

AtlasPngs encode_atlas_pngs(const image::Image& color, const image::Image& normal_depth) {
  AtlasPngs out;
  tbb::parallel_invoke([&] { out.color = image::encode_png(color, options()); },
                       [&] { out.normal_depth = image::encode_png(normal_depth, options()); });
  return out;
}

}  // namespace sylva::impostor
