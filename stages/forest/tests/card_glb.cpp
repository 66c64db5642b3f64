#include "stages/forest/tests/card_glb.h"

#include "libs/gltf/writer.h"
#include "libs/image/png.h"

namespace sylva::forest::testing {

std::string card_glb(double h, bool blend, bool normals) {
  gltf::Scene s;
  gltf::Image im;
  im.name = "impostor.png";
  const std::vector<std::uint8_t> png = image::encode_png(image::Image(2, 2, image::Rgba8{40, 90, 30, 255}));
  im.bytes.assign(png.begin(), png.end());
  s.images.push_back(im);
  gltf::Material m;
  m.name = "impostor";
  m.unlit = true;
  if (blend) m.alpha_mode = gltf::AlphaMode::kBlend;
  m.base_color_texture.image = 0;
  s.materials.push_back(m);
  gltf::Primitive p;
  const float fh = float(h);
  p.positions = {-1, 0, 0, 1, 0, 0, 1, fh, 0, -1, fh, 0};
  if (normals) p.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  p.texcoords = {0, 1, 1, 1, 1, 0, 0, 0};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.material = 0;
  gltf::Mesh mesh;
  mesh.name = "impostor";
  mesh.primitives.push_back(p);
  s.meshes.push_back(mesh);
  gltf::Node n;
  n.name = "impostor";
  n.mesh = 0;
  s.nodes.push_back(n);
  s.roots = {0};
  return gltf::encode(s);
}

}  // namespace sylva::forest::testing
