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

void write_atlas_pngs(const image::Image& color, const std::filesystem::path& color_path,
                      const image::Image& normal_depth, const std::filesystem::path& normal_depth_path) {
  tbb::parallel_invoke([&] { image::write_png(color, color_path, options()); },
                       [&] { image::write_png(normal_depth, normal_depth_path, options()); });
}

}  // namespace sylva::impostor
