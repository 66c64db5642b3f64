// Test doubles and fixtures for the verify tests: a fake Renderer whose pictures are exact and
// cheap, and tiny GLB scenes built with sylva_render_testing.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "libs/image/image.h"
#include "libs/render/camera.h"
#include "libs/render/renderer.h"

namespace sylva::verify::testing {

// Draws, for every camera, the background and one axis-aligned square of 30 x 30 pixels in the
// colour of the scene's first material, its top-left corner at (10 + tx, 10 + v) where tx is the
// x translation (metres, rounded) of the first instance of the first mesh and v the camera's
// index in the call. So moving an asset by 4 m along x moves its square by 4 pixels: on a
// 100 x 100 image 2 * 4 * 30 = 240 pixels (2.4 %) change.
class FakeRenderer final : public render::Renderer {
 public:
  std::vector<image::Image> render_views(const render::Scene& scene, std::span<const render::Camera> cameras,
                                         const render::RenderOptions& options) override;
  std::string device_description() const override { return "fake renderer (tests)"; }
  int calls = 0;        // render_views() calls
  int views_drawn = 0;  // images returned
};

// A GLB with one unit quad node at x = `tx` whose material has base colour `rgb` (linear).
void write_square_glb(const std::filesystem::path& path, float tx, float r = 0.8f, float g = 0.2f,
                      float b = 0.1f);

// A 100 x 100 camera set without MSAA and views named `views`.
render::CameraSet small_camera_set(const std::vector<std::string>& views = {"front", "side"}, int size = 100);

}  // namespace sylva::verify::testing
