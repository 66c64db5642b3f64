// impostor.glb through libs/gltf (impostor_gltf.h).
#include "stages/impostor/impostor_gltf.h"

#include "libs/gltf/writer.h"

namespace sylva::impostor {

std::size_t card_triangles(const std::vector<GlbCard>& cards) {
  std::size_t n = 0;
  for (const GlbCard& c : cards) n += c.card.cutout.size() >= 3 ? c.card.cutout.size() - 2 : 0;
  return n;
}

std::string encode_impostor_glb(const std::vector<GlbCard>& cards, const GlbImage& image, const GlbAlpha& alpha,
                                const nlohmann::json& extras) {
  gltf::Scene s;
  gltf::Image img;
  img.name = "impostor_cards.png";
  img.bytes = image.png;
  s.images.push_back(std::move(img));
  gltf::Material m;
  m.name = "impostor";
  m.base_color_texture.image = 0;
  m.base_color_texture.wrap_s = gltf::Wrap::kClampToEdge;
  m.base_color_texture.wrap_t = gltf::Wrap::kClampToEdge;
  m.alpha_mode = alpha.blend ? gltf::AlphaMode::kBlend : gltf::AlphaMode::kMask;
  m.alpha_cutoff = alpha.cutoff;
  m.metallic = 0;
  m.roughness = 1;
  m.unlit = true;  // the image is lit already (bake.h)
  s.materials.push_back(m);
  gltf::Primitive p;
  p.material = 0;
  for (const GlbCard& gc : cards) {
    const Card& c = gc.card;
    const std::uint32_t base = std::uint32_t(p.vertex_count());
    for (const auto& uv : c.cutout) {
      const double a = (2 * uv[0] - 1) * c.half_width, b = (1 - 2 * uv[1]) * c.half_height;
      for (int k = 0; k < 3; ++k) p.positions.push_back(float(c.center[k] + a * c.right[k] + b * c.up[k]));
      for (int k = 0; k < 3; ++k) p.normals.push_back(float(gc.normal[k]));
      p.texcoords.push_back(float((gc.image_x + uv[0] * c.w) / image.width));
      p.texcoords.push_back(float((gc.image_y + uv[1] * c.h) / image.height));
    }
    for (std::uint32_t i = 1; i + 1 < c.cutout.size(); ++i) {
      p.indices.push_back(base);
      p.indices.push_back(base + i);
      p.indices.push_back(base + i + 1);
    }
  }
  gltf::Mesh mesh;
  mesh.name = "impostor";
  mesh.primitives.push_back(std::move(p));
  s.meshes.push_back(std::move(mesh));
  gltf::Node node;
  node.name = "impostor";
  node.mesh = 0;
  node.extras = extras;
  s.nodes.push_back(std::move(node));
  s.roots = {0};
  s.extras = {{"sylva_stage", "impostor"}};
  return gltf::encode(s);
}

}  // namespace sylva::impostor
