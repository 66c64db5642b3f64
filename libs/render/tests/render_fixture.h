// The fixture and helpers of the renderer's pixel tests (render_test.cpp, render_calls_test.cpp):
// small hand-built glTF scenes rendered by one headless renderer per test suite, and pixels
// checked at chosen spots.
//
// These tests need EGL + OpenGL (Mesa llvmpipe). They skip only on a machine without any EGL
// vendor; with Mesa's EGL installed, or SYLVA_REQUIRE_GL=1, failing to create a renderer fails.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "libs/image/image_io.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/renderer.h"
#include "libs/render/testing/gltf_builder.h"
#include "libs/render/testing/headless_renderer_test.h"
#include "tests/support/test_support.h"

namespace sylva::render::render_test {

using image::Image;
using image::Rgba8;
using testing::GltfBuilder;
using testing::MaterialData;
using testing::NodeData;
using testing::PrimitiveData;

constexpr Rgba8 kBackground{191, 204, 217, 255};  // RenderOptions' default

// Linear [0, 1] -> 8-bit sRGB, as the fragment shader encodes.
inline int srgb8(double c) {
  c = std::clamp(c, 0.0, 1.0);
  const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return int(std::lround(s * 255.0));
}

inline ::testing::AssertionResult near(Rgba8 got, Rgba8 want, int tol = 1) {
  const bool ok = std::abs(got.r - want.r) <= tol && std::abs(got.g - want.g) <= tol &&
                  std::abs(got.b - want.b) <= tol && std::abs(got.a - want.a) <= tol;
  if (ok) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "got (" << int(got.r) << "," << int(got.g) << "," << int(got.b) << "," << int(got.a)
         << "), want (" << int(want.r) << "," << int(want.g) << "," << int(want.b) << "," << int(want.a)
         << ") +-" << tol;
}

// Pixel (column, row) where a world point lands.
inline Eigen::Vector2i project(const Camera& cam, const RenderOptions& o, const Vec3& p) {
  const Vec4 clip =
      cam.projection_matrix(float(o.width) / float(o.height)) * cam.view_matrix() * p.homogeneous();
  const float x = (clip.x() / clip.w() * 0.5f + 0.5f) * float(o.width);
  const float y = (0.5f - clip.y() / clip.w() * 0.5f) * float(o.height);
  return {int(std::floor(x)), int(std::floor(y))};
}

inline Camera look(const Vec3& eye, const Vec3& target = Vec3::Zero(), float fov = 45.f) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.fov_y_deg = fov;
  c.z_near = 0.05f;
  c.z_far = 50.f;
  return c;
}

inline RenderOptions small(int size = 64, int msaa = 4) {
  RenderOptions o;
  o.width = o.height = size;
  o.msaa = msaa;
  return o;
}

inline RenderOptions unlit_options(int size = 64, int msaa = 4) {
  RenderOptions o = small(size, msaa);
  o.lighting.ambient = Vec3::Ones();
  o.lighting.light_color = Vec3::Zero();
  return o;
}

class RenderTest : public testing::HeadlessRendererTest {
 protected:
  Scene load(const GltfBuilder& b, const std::string& name = "scene.glb") {
    b.write_glb(dir_ / name);
    return load_gltf_scene(dir_ / name);
  }

  Image render(const Scene& s, const Camera& c, const RenderOptions& o) { return renderer_->render(s, c, o); }

  // Writes the image under out/test-images/ for looking at it (not an assertion).
  static void keep(const Image& img, const std::string& name);

  test::TempDir dir_;
};

// A 2x2 texture: red, green / blue, white (top row first).
Image quadrant_texture();

// Horizontal lines one pixel apart, one per pixel row, at depth z (camera on +Z at distance 2,
// 45 degree fov, 64 pixels): rows [first, last).
PrimitiveData line_rows(float z, int first, int last, int material);

}  // namespace sylva::render::render_test
