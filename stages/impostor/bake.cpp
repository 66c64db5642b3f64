// The impostor core (bake.h lists the steps). Sources: Brucks 2018 (octahedral impostors), the
// SpeedTree billboard ring, Persson 2009 (cutouts), the LOD error model (docs/lod-model.md).
#include "stages/impostor/bake.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "libs/image/image_io.h"
#include "libs/impostor/error_model.h"
#include "libs/impostor/octahedral.h"
#include "stages/impostor/cutout.h"
#include "stages/impostor/dilate.h"
#include "stages/impostor/impostor_gltf.h"

namespace sylva::impostor {

namespace {

PixelRect rect_of(const render::BakeView& v) { return {v.x, v.y, v.w, v.h}; }

// Coverage-weighted mean of the decoded normals of a rectangle, and of its depths (-1..1).
struct FrameMeans {
  Vec3 normal = Vec3::Zero();
  double depth = 0;
  double coverage = 0;
};

FrameMeans frame_means(const image::Image& color, const image::Image& nd, const PixelRect& r) {
  FrameMeans m;
  const auto& cb = color.bytes();
  const auto& nb = nd.bytes();
  double depth_sum = 0;
  for (int y = r.y; y < r.y + r.h; ++y)
    for (int x = r.x; x < r.x + r.w; ++x) {
      const std::size_t i = (std::size_t(y) * std::size_t(color.width()) + std::size_t(x)) * 4;
      const double a = cb[i + 3] / 255.0;
      if (a <= 0) continue;
      m.coverage += a;
      m.normal += a * Vec3(nb[i] / 127.5 - 1, nb[i + 1] / 127.5 - 1, nb[i + 2] / 127.5 - 1);
      depth_sum += a * (nb[i + 3] / 127.5 - 1);
    }
  if (m.coverage > 0) m.depth = depth_sum / m.coverage;
  return m;
}

image::Image crop(const image::Image& src, const PixelRect& r) {
  image::Image out(r.w, r.h);
  for (int y = 0; y < r.h; ++y)
    std::copy_n(&src.bytes()[(std::size_t(r.y + y) * std::size_t(src.width()) + std::size_t(r.x)) * 4],
                std::size_t(r.w) * 4, &out.bytes()[std::size_t(y) * std::size_t(r.w) * 4]);
  return out;
}

void paste(image::Image& dst, const image::Image& src, int x, int y) {
  for (int row = 0; row < src.height(); ++row)
    std::copy_n(&src.bytes()[std::size_t(row) * std::size_t(src.width()) * 4], std::size_t(src.width()) * 4,
                &dst.bytes()[(std::size_t(y + row) * std::size_t(dst.width()) + std::size_t(x)) * 4]);
}

std::string to_string(const std::vector<std::uint8_t>& bytes) {
  return std::string(bytes.begin(), bytes.end());
}

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double linear_to_srgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}

// The colour map lit as the reference shader and the verifier light it (libs/render Lighting
// defaults; the mean normal keeps its length, so spread normals light like their mean), alpha
// unchanged: what impostor.glb's unlit cards show.
image::Image prelit(const image::Image& color, const image::Image& nd) {
  const render::Lighting light;
  const Vec3 l = light.direction_to_light.cast<double>().normalized();
  std::array<double, 256> lin{};
  for (int i = 0; i < 256; ++i) lin[std::size_t(i)] = srgb_to_linear(i / 255.0);
  image::Image out = color;
  auto& ob = out.bytes();
  const auto& nb = nd.bytes();
  for (std::size_t i = 0; i < ob.size(); i += 4) {
    Vec3 n(nb[i] / 127.5 - 1, nb[i + 1] / 127.5 - 1, nb[i + 2] / 127.5 - 1);
    if (n.norm() > 1) n.normalize();
    for (int c = 0; c < 3; ++c) {
      const double k = light.ambient[c] + light.light_color[c] * std::max(0.0, n.dot(l));
      ob[i + std::size_t(c)] =
          std::uint8_t(std::lround(255 * linear_to_srgb(lin[ob[i + std::size_t(c)]] * k)));
    }
  }
  return out;
}

// Where the trunk stands (x, z): every vertical card's frame shows the tree's lowest texels, the
// trunk's foot, at some offset along the card's `right`; the point whose offsets along every
// card's `right` best match them (least squares). The foot is the coverage-weighted mean column
// of a frame's lowest covered rows (the lowest 1 % of the frame's height, at least two rows). With
// fewer than two independent directions, the box centre.
std::array<double, 2> trunk_foot(const image::Image& color, const Layout& layout) {
  double a = 0, b = 0, c = 0, rx = 0, rz = 0;  // normal equations [a b; b c] f = (rx, rz)
  std::array<double, 2> centre{0, 0};
  for (std::size_t k = 0; k < layout.cards.size(); ++k) {
    const Card& card = layout.cards[k];
    if (std::abs(card.dir[1]) >= 0.5) continue;
    centre = {card.center[0], card.center[2]};
    const render::BakeView& v = layout.views[std::size_t(layout.card_view[k])];
    const auto& bytes = color.bytes();
    auto alpha = [&](int x, int y) {
      return bytes[(std::size_t(v.y + y) * std::size_t(color.width()) + std::size_t(v.x + x)) * 4 + 3] /
             255.0;
    };
    int lowest = -1;
    for (int y = v.h - 1; y >= 0 && lowest < 0; --y)
      for (int x = 0; x < v.w; ++x)
        if (alpha(x, y) > 0) {
          lowest = y;
          break;
        }
    if (lowest < 0) continue;
    const int rows = std::max(2, v.h / 100);
    double sum = 0, weight = 0;
    for (int y = std::max(0, lowest - rows + 1); y <= lowest; ++y)
      for (int x = 0; x < v.w; ++x) sum += alpha(x, y) * (x + 0.5), weight += alpha(x, y);
    const double u = sum / weight / v.w;
    const double m =
        card.center[0] * card.right[0] + card.center[2] * card.right[2] + (2 * u - 1) * card.half_width;
    a += card.right[0] * card.right[0], b += card.right[0] * card.right[2],
        c += card.right[2] * card.right[2];
    rx += card.right[0] * m, rz += card.right[2] * m;
  }
  const double det = a * c - b * b;
  if (std::abs(det) < 1e-6) return centre;
  return {(c * rx - b * rz) / det, (a * rz - b * rx) / det};
}

// 3. The bake's options: the atlas, MSAA and threads, and lines as wide as the pixel their alpha
// is for; thinner than a texel, one texel wide with their alpha scaled by how much of the texel
// they cover.
render::BakeOptions bake_options(const Layout& layout, const BakeParams& p, const SourceDesc& source,
                                 double texel) {
  render::BakeOptions bo;
  bo.atlas_width = layout.atlas_width;
  bo.atlas_height = layout.atlas_height;
  bo.msaa = p.msaa;
  bo.threads = p.threads;
  const double line_texels = source.line_pixel_m > 0 ? source.line_pixel_m / texel : 1.0;
  bo.line_width_px = float(std::max(1.0, line_texels));
  bo.line_alpha_scale = float(std::min(1.0, line_texels));
  return bo;
}

// 5a. Billboards: half of the vertical cards face any viewer near the horizon and all of them
// show the whole crown, so over each other they would cover 1 - (1 - c)^(K/2) where the tree
// covers c. Each vertical card's alpha becomes 1 - (1 - c)^(2/K), so that the K/2 together
// cover c (the lod stage's rule for its three lines per internode, docs/stages/lod.md). The
// first `cards` views are the vertical cards'.
void share_card_coverage(image::Image& color, const Layout& layout, int cards) {
  const double m = 0.5 * cards;
  std::array<std::uint8_t, 256> lut{};
  for (int a = 0; a < 256; ++a)
    lut[std::size_t(a)] = std::uint8_t(std::lround(255.0 * (1 - std::pow(1 - a / 255.0, 1 / m))));
  for (int k = 0; k < cards; ++k) {
    const render::BakeView& v = layout.views[std::size_t(k)];
    for (int y = v.y; y < v.y + v.h; ++y)
      for (int x = v.x; x < v.x + v.w; ++x) {
        std::uint8_t& a =
            color.bytes()[(std::size_t(y) * std::size_t(color.width()) + std::size_t(x)) * 4 + 3];
        a = lut[a];
      }
  }
}

// The cards as impostor.glb draws them, and the mean fraction of their frames their cutouts cover.
struct FittedCards {
  std::vector<GlbCard> cards;
  double cutout_fill = 1;
};

// 5-6. Cards: top-card height, normals, cutouts (layout.cards updated). Vertical cards stand
// through the trunk's foot rather than the box centre: moving a card along its own direction
// moves nothing of what its orthographic frame shows, and through the foot the trunk is drawn
// where it stands, so a card seen from aside, or edge-on as a line, puts the trunk on the tree's
// own trunk.
FittedCards fit_cards(const render::BakedMaps& maps, Layout& layout, const BakeParams& p, bool billboards) {
  const std::array<double, 2> foot = trunk_foot(maps.color, layout);
  FittedCards out;
  double fill = 0;
  for (std::size_t c = 0; c < layout.cards.size(); ++c) {
    Card& card = layout.cards[c];
    const render::BakeView& v = layout.views[std::size_t(layout.card_view[c])];
    const FrameMeans means = frame_means(maps.color, maps.normal_depth, rect_of(v));
    if (billboards && card.name == "top" && means.coverage > 0)
      card.center[1] += means.depth * v.depth_radius;  // the mean height of what is seen from above
    if (std::abs(card.dir[1]) < 0.5) {
      // Vertical cards stand through the trunk's foot, not the box centre (above).
      const double shift =
          (foot[0] - card.center[0]) * card.dir[0] + (foot[1] - card.center[2]) * card.dir[2];
      for (int k = 0; k < 3; ++k) card.center[std::size_t(k)] += shift * card.dir[std::size_t(k)];
      // A crown polygon and a trunk polygon (cutout.h fit_split_cutout says why).
      const SplitCutout cut = fit_split_cutout(maps.color, rect_of(v), p.cutout_vertices, p.cutout_vertices);
      card.cutout = cut.upper;
      card.lower_cutout = cut.lower;
      fill += cut.area_fraction;
    } else {
      const CutoutResult cut = fit_cutout(maps.color, rect_of(v), p.cutout_vertices);
      card.cutout = cut.polygon;
      fill += cut.area_fraction;
    }
    GlbCard g;
    g.card = card;
    const Vec3 dir(card.dir[0], card.dir[1], card.dir[2]);
    Vec3 n = means.normal.norm() > 1e-6 ? means.normal.normalized() : dir;
    if (n.dot(dir) <= 0.05) n = dir;  // a card must face its own viewer
    g.normal = {n.x(), n.y(), n.z()};
    out.cards.push_back(std::move(g));
  }
  out.cutout_fill = layout.cards.empty() ? 1.0 : fill / double(layout.cards.size());
  return out;
}

// 7. impostor.json's numbers: the atlas, the bounds, the error terms and the switch distance.
ImpostorInfo impostor_info(const BakeParams& p, const SourceGeometry& geo, const Layout& layout,
                           const SourceDesc& source, double texel, const std::vector<GlbCard>& glb_cards) {
  const bool billboards = p.layout.kind == Kind::kBillboards;
  ImpostorInfo info;
  info.kind = p.layout.kind;
  info.hemi = p.layout.kind == Kind::kHemiOctahedral;
  info.frames_per_side = billboards ? 0 : p.layout.frames_per_side;
  info.frame_px = p.layout.frame_px;
  info.atlas_width_px = layout.atlas_width;
  info.atlas_height_px = layout.atlas_height;
  info.padding_px = layout.padding_px;
  info.mip_levels = p.layout.mip_levels;
  info.bounds_min = geo.bounds_min;
  info.bounds_max = geo.bounds_max;
  info.sphere_center = geo.center;
  info.sphere_radius = geo.radius;
  info.frame_half_extent = layout.frame_half_extent;
  info.color_map = "impostor_color.png";
  info.normal_depth_map = "impostor_normal.png";
  info.camera = p.camera;
  info.pixel_error_px = p.pixel_error;
  info.error.source_m = source.epsilon;
  info.error.texel_m = texel;
  info.error.view_m = billboards
                          ? geo.radius * std::sin(billboard_max_view_angle(p.layout.cards, p.layout.top_card))
                          : geo.radius * view_error_factor(p.layout.frames_per_side, info.hemi);
  // The error model's distance, or the one a recipe records because impostorcheck proved it (the
  // error terms stay the model's: they say why the model's distance is what it is).
  info.switch_distance_m =
      p.switch_distance_m > 0 ? p.switch_distance_m : switch_distance(p.camera, info.error, p.pixel_error);
  info.source_type = source.type;
  info.source_file = source.file;
  info.source_level = source.level;
  info.cards = layout.cards;
  info.glb_triangles = card_triangles(glb_cards);
  return info;
}

// 8. impostor.glb's image: the colour map lit as the verifier lights the tree (so every viewer
// shows what sylva verifies); billboards embed the whole (small) atlas, the octahedral kinds a
// crop of their card frames, side by side (each card's image_x, image_y set).
GlbImage glb_image(const render::BakedMaps& maps, std::vector<GlbCard>& glb_cards, const BakeParams& p,
                   bool billboards) {
  GlbImage img;
  if (billboards) {
    const image::Image lit = prelit(maps.color, maps.normal_depth);
    img.png = to_string(image::encode_png(lit));
    img.width = maps.color.width();
    img.height = maps.color.height();
    for (GlbCard& g : glb_cards) g.image_x = g.card.x, g.image_y = g.card.y;
  } else {
    const int f = p.layout.frame_px, cols = 2;
    const int rows = int((glb_cards.size() + cols - 1) / cols);
    image::Image sheet(cols * f, rows * f, {0, 0, 0, 0});
    for (std::size_t c = 0; c < glb_cards.size(); ++c) {
      GlbCard& g = glb_cards[c];
      g.image_x = int(c % cols) * f;
      g.image_y = int(c / cols) * f;
      // Only the card frames are lit (4 of 256 frames): the rest of the atlas never shows in the GLB.
      const PixelRect r{g.card.x, g.card.y, g.card.w, g.card.h};
      paste(sheet, prelit(crop(maps.color, r), crop(maps.normal_depth, r)), g.image_x, g.image_y);
    }
    img.png = to_string(image::encode_png(sheet));
    img.width = sheet.width();
    img.height = sheet.height();
  }
  return img;
}

}  // namespace

BakeOutput bake_impostor(render::ImpostorRenderer& renderer, const render::Scene& scene, const BakeParams& p,
                         const SourceDesc& source) {
  if (p.cutout_vertices < 4 || p.cutout_vertices > 8)
    throw std::invalid_argument("cutout_vertices must be in 4..8");
  // 1-2. Measure and plan.
  const SourceGeometry geo = measure(scene);
  Layout layout = plan_layout(p.layout, geo);
  const bool billboards = p.layout.kind == Kind::kBillboards;
  const double texel = 2 * layout.frame_half_extent / p.layout.frame_px;

  // 3. Bake.
  render::BakedMaps maps = renderer.bake(scene, layout.views, bake_options(layout, p, source, texel));

  // 4. Dilate.
  std::vector<PixelRect> rects;
  for (const render::BakeView& v : layout.views) rects.push_back(rect_of(v));
  dilate_frames(maps.color, maps.normal_depth, rects, layout.padding_px);

  // 5-6. Billboards' coverage shared among their cards; every card fitted.
  if (billboards && p.layout.cards >= 2) share_card_coverage(maps.color, layout, p.layout.cards);
  FittedCards fitted = fit_cards(maps, layout, p, billboards);

  // 7. Error terms and switch distance.
  ImpostorInfo info = impostor_info(p, geo, layout, source, texel, fitted.cards);

  // 8. impostor.glb.
  const GlbImage img = glb_image(maps, fitted.cards, p, billboards);
  const nlohmann::json extras = {{"sylva_impostor_kind", kind_name(info.kind)},
                                 {"switch_distance_m", info.switch_distance_m},
                                 {"epsilon_m", info.error.epsilon_m()},
                                 {"impostor_json", kImpostorJsonFile}};

  BakeOutput out;
  out.glb = encode_impostor_glb(fitted.cards, img, p.glb_alpha, extras);
  out.info = std::move(info);
  out.color = std::move(maps.color);
  out.normal_depth = std::move(maps.normal_depth);
  out.cutout_fill = fitted.cutout_fill;
  return out;
}

}  // namespace sylva::impostor
