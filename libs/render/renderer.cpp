// The renderer's calls that need no device (renderer.h): they hold for any Renderer.
#include "libs/render/renderer.h"

namespace sylva::render {

RenderOptions options_for(const CameraSet& set, RenderOptions base) {
  base.width = set.width;
  base.height = set.height;
  base.msaa = set.msaa;
  base.supersample = set.supersample;
  return base;
}

std::vector<RenderedView> render_camera_set(Renderer& renderer, const Scene& scene, const CameraSet& set,
                                            const RenderOptions& base) {
  const RenderOptions options = options_for(set, base);
  const Bounds bounds = scene.bounds();
  const float aspect = float(options.width) / float(options.height);
  std::vector<Camera> cameras;
  for (const CameraView& v : set.views) cameras.push_back(resolve(v, bounds, aspect));
  std::vector<image::Image> images = renderer.render_views(scene, cameras, options);
  std::vector<RenderedView> out;
  for (std::size_t i = 0; i < cameras.size(); ++i) out.push_back({cameras[i], std::move(images[i])});
  return out;
}

}  // namespace sylva::render
