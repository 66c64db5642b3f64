// The bodies of the pixel tests' fixture and helpers (render_fixture.h) that are not one-liners.
#include "libs/render/tests/render_fixture.h"

namespace sylva::render::render_test {

void RenderTest::keep(const Image& img, const std::string& name) {
  std::filesystem::create_directories("out/test-images");
  image::write_png(img, "out/test-images/" + name + ".png");
}

Image quadrant_texture() {
  Image t(2, 2);
  t.set(0, 0, {255, 0, 0, 255});
  t.set(1, 0, {0, 255, 0, 255});
  t.set(0, 1, {0, 0, 255, 255});
  t.set(1, 1, {255, 255, 255, 255});
  return t;
}

PrimitiveData line_rows(float z, int first, int last, int material) {
  PrimitiveData p;
  p.mode = TINYGLTF_MODE_LINE;
  p.material = material;
  const float pixel = 2.f * (2.f - z) * std::tan(22.5f * 3.14159265f / 180.f) / 64.f;
  for (int r = first; r < last; ++r) {
    const float y = (32.f - float(r) - 0.5f) * pixel;
    p.positions.emplace_back(-3.f, y, z);
    p.positions.emplace_back(3.f, y, z);
  }
  return p;
}

}  // namespace sylva::render::render_test
