// impostor.glb through libs/gltf (impostor_gltf.h).
#include "stages/impostor/impostor_gltf.h"

#include <cmath>

#include "libs/gltf/writer.h"

namespace sylva::impostor {

namespace {

using Uv = std::array<double, 2>;

bool vertical(const Card& c) { return std::abs(c.dir[1]) < 0.5; }

// The part of convex polygon `poly` on one side of the line u = 1/2 (left: u <= 1/2), by
// Sutherland-Hodgman; consecutive duplicates dropped.
std::vector<Uv> clip_half(const std::vector<Uv>& poly, bool left) {
  std::vector<Uv> out;
  auto inside = [&](const Uv& p) { return left ? p[0] <= 0.5 : p[0] >= 0.5; };
  auto push = [&](const Uv& p) {
    if (out.empty() || std::abs(out.back()[0] - p[0]) + std::abs(out.back()[1] - p[1]) > 1e-12)
      out.push_back(p);
  };
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Uv& a = poly[i];
    const Uv& b = poly[(i + 1) % poly.size()];
    if (inside(a)) push(a);
    if ((a[0] - 0.5) * (b[0] - 0.5) < 0) {
      const double t = (0.5 - a[0]) / (b[0] - a[0]);
      push({0.5, a[1] + t * (b[1] - a[1])});
    }
  }
  if (out.size() > 1 &&
      std::abs(out.front()[0] - out.back()[0]) + std::abs(out.front()[1] - out.back()[1]) <= 1e-12)
    out.pop_back();
  return out;
}

double area(const std::vector<Uv>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Uv& u = p[i];
    const Uv& v = p[(i + 1) % p.size()];
    a += u[0] * v[1] - v[0] * u[1];
  }
  return 0.5 * std::abs(a);
}

}  // namespace

std::vector<std::vector<std::array<double, 2>>> card_pieces(const Card& c) {
  std::vector<std::vector<Uv>> out;
  for (const std::vector<Uv>* poly : {&c.cutout, &c.lower_cutout}) {
    if (poly->empty()) continue;
    if (!vertical(c)) {
      out.push_back(*poly);
      continue;
    }
    for (bool left : {true, false}) {
      std::vector<Uv> half = clip_half(*poly, left);
      if (half.size() >= 3 && area(half) > 1e-9) out.push_back(std::move(half));
    }
  }
  return out;
}

std::size_t card_triangles(const std::vector<GlbCard>& cards) {
  std::size_t n = 0;
  for (const GlbCard& c : cards)
    for (const auto& piece : card_pieces(c.card)) n += piece.size() - 2;
  return n;
}

std::string encode_impostor_glb(const std::vector<GlbCard>& cards, const GlbImage& image,
                                const GlbAlpha& alpha, const nlohmann::json& extras) {
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
  gltf::Mesh mesh;
  mesh.name = "impostor";
  // One primitive per piece (half card): viewers sort blended primitives far to near by their
  // bounds' centre (three.js per primitive, sylva's renderer per primitive and then per
  // triangle), and half-planes around one axis are ordered correctly that way.
  for (const GlbCard& gc : cards) {
    const Card& c = gc.card;
    for (const auto& piece : card_pieces(c)) {
      gltf::Primitive p;
      p.material = 0;
      for (const auto& uv : piece) {
        const double a = (2 * uv[0] - 1) * c.half_width, b = (1 - 2 * uv[1]) * c.half_height;
        for (int k = 0; k < 3; ++k) p.positions.push_back(float(c.center[k] + a * c.right[k] + b * c.up[k]));
        for (int k = 0; k < 3; ++k) p.normals.push_back(float(gc.normal[k]));
        p.texcoords.push_back(float((gc.image_x + uv[0] * c.w) / image.width));
        p.texcoords.push_back(float((gc.image_y + uv[1] * c.h) / image.height));
      }
      for (std::uint32_t i = 1; i + 1 < piece.size(); ++i) {
        p.indices.push_back(0);
        p.indices.push_back(i);
        p.indices.push_back(i + 1);
      }
      mesh.primitives.push_back(std::move(p));
    }
  }
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
