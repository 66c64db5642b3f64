#include "stages/verify/tests/fake_renderer.h"

#include <cmath>

#include "libs/render/testing/gltf_builder.h"

namespace sylva::verify::testing {

std::vector<image::Image> FakeRenderer::render_views(const render::Scene& scene,
                                                     std::span<const render::Camera> cameras,
                                                     const render::RenderOptions& options) {
  ++calls;
  int tx = 0;
  if (!scene.meshes.empty() && !scene.meshes[0].instances.empty())
    tx = static_cast<int>(std::lround(scene.meshes[0].instances[0](0, 3)));
  image::Rgba8 color{200, 50, 25, 255};
  if (!scene.materials.empty()) {
    const auto& c = scene.materials[0].base_color;
    color = {static_cast<std::uint8_t>(std::lround(c.x() * 255)),
             static_cast<std::uint8_t>(std::lround(c.y() * 255)),
             static_cast<std::uint8_t>(std::lround(c.z() * 255)), 255};
  }
  std::vector<image::Image> out;
  for (std::size_t v = 0; v < cameras.size(); ++v) {
    image::Image img(options.width, options.height, options.background);
    const int x0 = 10 + tx, y0 = 10 + static_cast<int>(v);
    for (int y = y0; y < y0 + 30; ++y)
      for (int x = x0; x < x0 + 30; ++x)
        if (x >= 0 && y >= 0 && x < img.width() && y < img.height()) img.set(x, y, color);
    out.push_back(std::move(img));
    ++views_drawn;
  }
  return out;
}

void write_square_glb(const std::filesystem::path& path, float tx, float r, float g, float b) {
  render::testing::GltfBuilder builder;
  const int mat = builder.add_material({.base_color = render::Vec4(r, g, b, 1.f)});
  const int mesh = builder.add_mesh({render::testing::quad(1.f, mat)}, "square");
  builder.add_root(builder.add_node({.mesh = mesh, .translation = render::Vec3(tx, 0, 0)}));
  builder.write_glb(path);
}

render::CameraSet small_camera_set(const std::vector<std::string>& views, int size) {
  std::string yaml = "version: 1\nwidth: " + std::to_string(size) + "\nheight: " + std::to_string(size) +
                     "\nmsaa: 1\nviews:\n";
  int az = 0;
  for (const auto& v : views) {
    yaml += "  - name: " + v + "\n    orbit: { azimuth_deg: " + std::to_string(az) + " }\n";
    az += 90;
  }
  return render::parse_camera_set(yaml, "test-cameras.yaml");
}

}  // namespace sylva::verify::testing
