// The baker and the reference shader on a hand-built box (libs/render/impostor_renderer.h through
// the stage core): every frame shows the box where the frame's formula puts it, with its colour,
// the normal of the face that faces the frame and a depth in front of its centre; the bytes do
// not depend on the thread count; drawn from a frame direction the impostor covers what the box
// covers, at every mip level.
#include "stages/impostor/bake.h"

#include <gtest/gtest.h>

#include <cmath>

#include "libs/image/coverage.h"
#include "libs/image/resample.h"
#include "libs/render/camera.h"
#include "libs/render/distance_camera.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/line_merge.h"
#include "libs/render/shared_renderer.h"
#include "stages/impostor/check/subject.h"

namespace sylva::impostor {
namespace {

const Vec3 kBoxCentre(0.5, 1.5, -0.3);

// An opaque red box of half size 1 at kBoxCentre, outward normals, counter-clockwise faces.
render::Scene box_scene() {
  render::Scene s;
  render::Material m;
  m.name = "red";
  m.base_color = render::Vec4(1, 0, 0, 1);
  s.materials.push_back(m);
  render::Primitive p;
  p.material = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      render::Vec3 n = render::Vec3::Zero();
      n[axis] = float(sign);
      const render::Vec3 u = render::Vec3::Unit((axis + 1) % 3), v = render::Vec3::Unit((axis + 2) % 3);
      const render::Vec3 c = kBoxCentre.cast<float>() + n;
      const std::uint32_t base = std::uint32_t(p.positions.size());
      for (auto [a, b] : {std::pair{-1.f, -1.f}, {1.f, -1.f}, {1.f, 1.f}, {-1.f, 1.f}}) {
        p.positions.push_back(c + a * u + b * v);
        p.normals.push_back(n);
      }
      const bool ccw = u.cross(v).dot(n) > 0;
      for (std::uint32_t i :
           ccw ? std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3} : std::vector<std::uint32_t>{0, 2, 1, 0, 3, 2})
        p.indices.push_back(base + i);
    }
  render::Mesh mesh;
  mesh.primitives.push_back(std::move(p));
  mesh.instances.push_back(render::Mat4::Identity());
  s.meshes.push_back(std::move(mesh));
  return s;
}

BakeParams small_params(Kind kind = Kind::kHemiOctahedral) {
  BakeParams p;
  p.layout.kind = kind;
  p.layout.frames_per_side = 4;
  p.layout.frame_px = 64;
  p.layout.mip_levels = 2;
  p.threads = 1;
  return p;
}

TEST(Bake, EveryFrameShowsTheBoxWhereItsFormulaSays) {
  const BakeOutput b = bake_impostor(render::shared_impostor_renderer(), box_scene(), small_params(), {});
  const ImpostorInfo& info = b.info;
  ASSERT_EQ(b.color.width(), 256);
  const Vec3 c(info.sphere_center[0], info.sphere_center[1], info.sphere_center[2]);
  EXPECT_NEAR(info.sphere_radius, std::sqrt(3.0), 1e-3);  // the box's corners
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const Vec3 d = frame_direction(i, j, 4, true);
      const FrameBasis fb = frame_basis(d);
      const Vec3 a = kBoxCentre - c;
      const int x = int(std::floor((i + 0.5 + a.dot(fb.right) / (2 * info.frame_half_extent)) * 64));
      const int y = int(std::floor((j + 0.5 - a.dot(fb.up) / (2 * info.frame_half_extent)) * 64));
      const image::Rgba8 col = b.color.at(x, y);
      EXPECT_EQ(col.a, 255) << i << "," << j;
      EXPECT_EQ(col.r, 255) << i << "," << j;
      EXPECT_EQ(col.g, 0) << i << "," << j;
      EXPECT_EQ(b.color.at(i * 64 + 1, j * 64 + 1).a, 0) << "corner of frame " << i << "," << j;
      // The normal of the face turned most toward the frame.
      Vec3 best = Vec3::Zero();
      for (int k = 0; k < 3; ++k)
        for (int s : {-1, 1}) {
          Vec3 n = Vec3::Zero();
          n[k] = s;
          if (n.dot(d) > best.dot(d)) best = n;
        }
      const image::Rgba8 nd = b.normal_depth.at(x, y);
      const Vec3 n(nd.r / 127.5 - 1, nd.g / 127.5 - 1, nd.b / 127.5 - 1);
      EXPECT_GT(n.dot(best), 0.97) << i << "," << j;
      // Depth: the first surface along the frame's ray through the centre lies in front of it,
      // by at most the half diagonal.
      const double h = (nd.a / 255.0 * 2 - 1) * info.sphere_radius, hc = a.dot(d);
      EXPECT_GT(h, hc + 0.5) << i << "," << j;
      EXPECT_LT(h, hc + std::sqrt(3.0) + 0.05) << i << "," << j;
    }
}

TEST(Bake, BytesDoNotDependOnTheThreadCount) {
  BakeParams p = small_params();
  const BakeOutput one = bake_impostor(render::shared_impostor_renderer(), box_scene(), p, {});
  p.threads = 3;
  const BakeOutput three = bake_impostor(render::shared_impostor_renderer(), box_scene(), p, {});
  EXPECT_EQ(one.color, three.color);
  EXPECT_EQ(one.normal_depth, three.normal_depth);
  EXPECT_EQ(one.glb, three.glb);
  EXPECT_EQ(write_impostor_json(one.info), write_impostor_json(three.info));
}

// Seen along a frame's own direction the reference shader covers what the box covers, and the
// coverage holds as the impostor shrinks through the mip levels (alpha is coverage, so the mips'
// averages keep it).
TEST(Bake, TheImpostorCoversWhatTheBoxCoversAtEveryMipLevel) {
  BakeParams p = small_params();
  p.layout.frames_per_side = 8;
  p.layout.frame_px = 128;
  p.layout.mip_levels = 4;
  const render::Scene box = box_scene();
  const BakeOutput b = bake_impostor(render::shared_impostor_renderer(), box, p, {});
  const render::OctahedralImpostor imp = octahedral_of(b.info, b.color, b.normal_depth);
  render::RenderOptions ro;
  ro.width = ro.height = 128;
  ro.background.a = 0;
  const double az =
      std::atan2(frame_direction(7, 0, 8, true).x(), frame_direction(7, 0, 8, true).z()) * 180 / M_PI;
  for (double d : {8.0, 32.0, 128.0}) {  // the box spans ~60, ~15 and ~4 pixels
    const render::Camera cam = render::camera_at_box_distance(box.bounds(), d, az, 0, M_PI / 8);
    const image::Image ref = render::shared_renderer().render(box, cam, ro);
    const image::Image test =
        render::shared_impostor_renderer().render_octahedral(imp, {&cam, 1}, ro).front();
    double a_ref = 0, a_test = 0;
    for (std::size_t i = 3; i < ref.bytes().size(); i += 4)
      a_ref += ref.bytes()[i], a_test += test.bytes()[i];
    EXPECT_NEAR(a_test / a_ref, 1.0, 0.06) << "distance " << d;
    const image::FootprintStats f = image::footprint_stats(ref, test, 0.5);
    EXPECT_LT(f.failing_fraction, 0.05) << "distance " << d;
    EXPECT_LT(f.shade_mean_error, 0.03) << "distance " << d;  // lit like the renderer
  }
}

// A tree's silhouette: a round crown (a sphere of radius 5 centred 9 m up, 2 m beside the trunk)
// over a narrow trunk (a box 0.5 m wide, 6 m tall) standing at the origin.
render::Scene lollipop_scene() {
  render::Scene s;
  render::Material m;
  m.name = "green";
  m.base_color = render::Vec4(0.2f, 0.6f, 0.2f, 1);
  s.materials.push_back(m);
  render::Primitive p;
  p.material = 0;
  const int rings = 12, segments = 24;
  const render::Vec3 c(-2, 9, 1);
  for (int i = 0; i <= rings; ++i)
    for (int k = 0; k <= segments; ++k) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * k / segments;
      const render::Vec3 n(float(std::sin(th) * std::cos(ph)), float(std::cos(th)),
                           float(std::sin(th) * std::sin(ph)));
      p.positions.push_back(c + 5.f * n);
      p.normals.push_back(n);
    }
  for (int i = 0; i < rings; ++i)
    for (int k = 0; k < segments; ++k) {
      const std::uint32_t a = std::uint32_t(i * (segments + 1) + k), b = a + std::uint32_t(segments + 1);
      for (std::uint32_t q : {a, a + 1, b, a + 1, b + 1, b}) p.indices.push_back(q);
    }
  s.materials[0].double_sided = true;
  render::Mesh crown;
  crown.primitives.push_back(std::move(p));
  crown.instances.push_back(render::Mat4::Identity());
  s.meshes.push_back(std::move(crown));
  render::Scene trunk = box_scene();
  render::Mat4 t = render::Mat4::Identity();
  t(0, 0) = 0.25f, t(2, 2) = 0.25f, t(1, 1) = 3.f;  // half sizes 0.25, 3, 0.25
  t(0, 3) = -0.25f * float(kBoxCentre.x()), t(1, 3) = 3.f - 3.f * float(kBoxCentre.y()),
       t(2, 3) = -0.25f * float(kBoxCentre.z());
  trunk.meshes[0].instances[0] = t;
  trunk.meshes[0].primitives[0].material = 1;
  s.materials.push_back(trunk.materials[0]);
  s.meshes.push_back(std::move(trunk.meshes[0]));
  return s;
}

// impostor.glb seen as viewers frame a file (orbits about its bounds' centre, as sylva's verify
// views: azimuths 0, 90, 180, 270) draws nothing below the lowest row the tree itself covers from
// the same camera. One convex 8-gon around crown and trunk had fictitious corners at or below
// ground level beside the trunk; the cross's other plane, a sliver nearly edge-on in these views
// and sampled at its coarsest mip, drew them as a stray line below the tree (cutout.h
// fit_split_cutout). Billboards from the front views alike.
TEST(Bake, ImpostorGlbDrawsNothingBelowTheTreeInAxisViews) {
  const render::Scene tree = lollipop_scene();
  for (Kind kind : {Kind::kHemiOctahedral, Kind::kBillboards}) {
    BakeParams p = small_params(kind);
    p.layout.frames_per_side = 8;
    p.layout.frame_px = 256;
    p.layout.mip_levels = 4;
    const BakeOutput b = bake_impostor(render::shared_impostor_renderer(), tree, p, {});
    const render::Scene glb = render::load_gltf_scene_from_memory(b.glb, "impostor.glb");
    render::RenderOptions ro;
    ro.width = ro.height = 384;
    ro.background.a = 0;
    for (double az : {0.0, 90.0, 180.0, 270.0})
      for (double el : {5.0, 15.0}) {
        render::CameraView view;
        view.fov_y_deg = 35;
        view.placement = render::OrbitView{float(az), float(el), 1.05f, 0.f};
        const render::Camera cam = render::resolve(view, glb.bounds(), 1.f);
        auto lowest_row = [](const image::Image& im) {
          int lowest = -1;
          for (int y = 0; y < im.height(); ++y)
            for (int x = 0; x < im.width(); ++x)
              if (im.bytes()[(std::size_t(y) * std::size_t(im.width()) + std::size_t(x)) * 4 + 3] > 0)
                lowest = y;
          return lowest;
        };
        const int tree_lowest = lowest_row(render::shared_renderer().render(tree, cam, ro));
        const int cards_lowest = lowest_row(render::shared_renderer().render(glb, cam, ro));
        ASSERT_GT(tree_lowest, 0);
        EXPECT_LE(cards_lowest, tree_lowest + 1)
            << kind_name(kind) << ", azimuth " << az << ", elevation " << el << ": the cards reach "
            << cards_lowest - tree_lowest << " rows below the tree";
      }
  }
}

// Twelve internodes fanning out from (0, 1, 0) over the box, each drawn as the lod stage draws a
// sub-pixel branch: three blended lines of alpha 0.3 on the same endpoints with normals 120 degrees
// apart. With `apart`, every copy gets its own texcoords (unused: the material has no texture),
// which keeps the baker from merging them (line_merge.h).
render::Scene twig_scene(bool apart) {
  render::Scene s = box_scene();
  render::Material m;
  m.name = "twigs";
  m.base_color = render::Vec4(0.3f, 0.2f, 0.1f, 1);
  m.alpha_mode = render::AlphaMode::kBlend;
  s.materials.push_back(m);
  render::Primitive p;
  p.topology = render::Topology::kLines;
  p.material = 1;
  const render::Vec3 root(0, 1, 0);
  for (int i = 0; i < 12; ++i) {
    const double az = 2 * M_PI * i / 12, el = 0.3 + 0.1 * (i % 4);
    const render::Vec3 axis(float(std::cos(el) * std::cos(az)), float(std::sin(el)),
                            float(std::cos(el) * std::sin(az)));
    const render::Vec3 n0 = axis.cross(render::Vec3::UnitY()).normalized(), b0 = axis.cross(n0);
    for (int c = 0; c < 3; ++c) {
      const double a = 2 * M_PI * c / 3;
      const render::Vec3 n = float(std::cos(a)) * n0 + float(std::sin(a)) * b0;
      const auto base = std::uint32_t(p.positions.size());
      for (float t : {0.2f, 3.5f}) {
        p.positions.push_back(root + t * axis);
        p.normals.push_back(n);
        p.colors.push_back({1, 1, 1, 0.3f});
        p.texcoords.push_back({apart ? float(c) : 0.f, t});
      }
      p.indices.insert(p.indices.end(), {base, base + 1});
    }
  }
  s.meshes[0].primitives.push_back(std::move(p));
  return s;
}

// The three lines of an internode, merged into one line of their composite, bake what the three
// overs bake: the same coverage, colour, normal and depth within 8-bit rounding, and a texel one
// internode covers holds 1 - 0.7^3 of coverage.
TEST(Bake, CoincidentBlendedLinesBakeAsTheirComposite) {
  const render::Scene merged_scene = twig_scene(false), apart_scene = twig_scene(true);
  ASSERT_EQ(render::merge_coincident_lines(merged_scene.meshes[0].primitives[1]).positions.size(), 24u);
  ASSERT_EQ(render::merge_coincident_lines(apart_scene.meshes[0].primitives[1]).positions.size(), 72u);
  BakeParams p = small_params();
  p.layout.frame_px = 128;
  const BakeOutput merged = bake_impostor(render::shared_impostor_renderer(), merged_scene, p, {});
  const BakeOutput apart = bake_impostor(render::shared_impostor_renderer(), apart_scene, p, {});
  ASSERT_EQ(merged.color.width(), apart.color.width());
  int worst_color = 0, worst_normal = 0, one_internode = 0;
  double cover_merged = 0, cover_apart = 0;
  const auto &cm = merged.color.bytes(), &ca = apart.color.bytes();
  const auto &nm = merged.normal_depth.bytes(), &na = apart.normal_depth.bytes();
  for (std::size_t i = 0; i < cm.size(); ++i) {
    worst_color = std::max(worst_color, std::abs(int(cm[i]) - int(ca[i])));
    worst_normal = std::max(worst_normal, std::abs(int(nm[i]) - int(na[i])));
  }
  for (std::size_t i = 3; i < cm.size(); i += 4) {
    cover_merged += cm[i], cover_apart += ca[i];
    if (std::abs(int(cm[i]) - int(std::lround(255 * (1 - 0.343)))) <= 2) ++one_internode;
  }
  EXPECT_LE(worst_color, 3);
  EXPECT_LE(worst_normal, 3);
  EXPECT_NEAR(cover_merged / cover_apart, 1.0, 0.002);
  EXPECT_GT(one_internode, 200);
}

// The packed opaque layer and the blended layers composited on read-back (render::BakeOptions::
// pack_opaque, the default with msaa 1) bake what drawing every primitive into the three maps'
// attachments bakes: the same bytes where only opaque primitives are, within two levels per
// channel where lines blend (the three attachments hold the lines' colour in 8 bits, the blended
// layers in 16), the same coverage. Multisampled bakes and opaque lines of fractional alpha take
// the three attachments.
TEST(Bake, ThePackedOpaqueLayerBakesWhatTheThreeAttachmentsBake) {
  render::ImpostorRenderer& r = render::shared_impostor_renderer();
  BakeParams p = small_params();
  p.layout.frame_px = 128;
  auto bake_both = [&](const render::Scene& scene) {
    const Layout layout = plan_layout(p.layout, measure(scene));
    render::BakeOptions o;
    o.atlas_width = layout.atlas_width;
    o.atlas_height = layout.atlas_height;
    o.msaa = 1;
    o.line_alpha_scale = 0.5f;  // the twigs are blended: they may carry it
    std::pair<render::BakedMaps, render::BakedMaps> out{r.bake(scene, layout.views, o), {}};
    o.pack_opaque = false;
    out.second = r.bake(scene, layout.views, o);
    EXPECT_TRUE(out.first.packed_opaque);
    EXPECT_FALSE(out.second.packed_opaque);
    return out;
  };
  const auto box = bake_both(box_scene());
  EXPECT_EQ(box.first.color, box.second.color);
  EXPECT_EQ(box.first.normal_depth, box.second.normal_depth);

  const auto [packed, three] = bake_both(twig_scene(false));
  int worst = 0, covered = 0;
  double cover_packed = 0, cover_three = 0;
  for (const auto& [a, b] :
       {std::pair{&packed.color, &three.color}, {&packed.normal_depth, &three.normal_depth}})
    for (std::size_t i = 0; i < a->bytes().size(); ++i)
      worst = std::max(worst, std::abs(int(a->bytes()[i]) - int(b->bytes()[i])));
  for (std::size_t i = 3; i < packed.color.bytes().size(); i += 4) {
    cover_packed += packed.color.bytes()[i], cover_three += three.color.bytes()[i];
    covered += three.color.bytes()[i] > 0;
  }
  ASSERT_GT(covered, 20000);
  EXPECT_LE(worst, 2);
  EXPECT_NEAR(cover_packed / cover_three, 1.0, 0.001);

  // msaa 2, or an opaque line carrying a fractional alpha: the three attachments.
  const render::Scene twigs = twig_scene(false);
  const Layout layout = plan_layout(p.layout, measure(twigs));
  render::BakeOptions o;
  o.atlas_width = layout.atlas_width;
  o.atlas_height = layout.atlas_height;
  o.msaa = 2;
  EXPECT_FALSE(r.bake(twigs, layout.views, o).packed_opaque);
  render::Scene opaque_twigs = twigs;
  opaque_twigs.materials[1].alpha_mode = render::AlphaMode::kOpaque;
  o.msaa = 1;
  o.line_alpha_scale = 0.5f;
  EXPECT_FALSE(r.bake(opaque_twigs, layout.views, o).packed_opaque);
  o.line_alpha_scale = 1;
  EXPECT_TRUE(r.bake(opaque_twigs, layout.views, o).packed_opaque);
}

// Textures are sampled from their nearest mip level (bilinearly within it), not blended between
// two. A horizontal quad under a 4 x 4 red/green checker repeated so that the frame looking
// straight down reads it at mip level ~0.75: level 1 (2 x 2 texel averages of the checker) is one
// colour, so the nearest level paints the whole quad one colour; trilinear filtering would mix a
// quarter of level 0's checker in.
TEST(Bake, TexturesAreSampledFromTheirNearestMipLevel) {
  render::Scene s;
  render::Texture t;
  t.name = "checker";
  t.width = t.height = 4;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      const bool red = (x + y) % 2 == 0;
      t.rgba.insert(t.rgba.end(), {std::uint8_t(red ? 255 : 0), std::uint8_t(red ? 0 : 255), 0, 255});
    }
  s.textures.push_back(t);
  render::Material m;
  m.name = "checker";
  m.base_color_texture = 0;
  m.double_sided = true;
  s.materials.push_back(m);
  // Frames of 64 px with 4 px of padding: the quad (half size 1, radius sqrt 2) spans
  // 2 / (2 W) 64 = 56 / sqrt 2 = 39.6 texels; 16.6 repeats of 4 texels over them: mip level
  // log2(66.4 / 39.6) = 0.75.
  const float uv = 16.6f;
  render::Primitive p;
  p.material = 0;
  p.positions = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  p.normals.assign(4, render::Vec3(0, 1, 0));
  p.texcoords = {{0, 0}, {uv, 0}, {uv, uv}, {0, uv}};
  p.indices = {0, 2, 1, 0, 3, 2};
  render::Mesh mesh;
  mesh.primitives.push_back(p);
  mesh.instances.push_back(render::Mat4::Identity());
  s.meshes.push_back(mesh);
  BakeParams bp = small_params();
  bp.layout.frames_per_side = 3;  // frame (1, 1) looks straight down
  bp.layout.mip_levels = 2;
  const BakeOutput b = bake_impostor(render::shared_impostor_renderer(), s, bp, {});
  int lo = 255, hi = 0, covered = 0;
  for (int y = 64; y < 128; ++y)
    for (int x = 64; x < 128; ++x) {
      const image::Rgba8 c = b.color.at(x, y);
      if (c.a < 255) continue;
      ++covered;
      lo = std::min(lo, int(c.r)), hi = std::max(hi, int(c.r));
    }
  EXPECT_GT(covered, 1200);
  EXPECT_LE(hi - lo, 1) << "red from " << lo << " to " << hi;
}

TEST(Bake, BadRequestsAreRenderErrors) {
  render::ImpostorRenderer& r = render::shared_impostor_renderer();
  render::BakeView v;
  v.x = 60, v.w = 10;
  render::BakeOptions o;
  o.atlas_width = o.atlas_height = 64;
  try {
    r.bake(box_scene(), {&v, 1}, o);
    FAIL();
  } catch (const render::RenderError& e) {
    EXPECT_STREQ(e.what(), "bake view 0 lies outside the atlas");
  }
  render::OctahedralImpostor imp;
  imp.geometry.frames_per_side = 4;
  imp.geometry.frame_px = 64;
  imp.color = image::Image(100, 100);
  imp.normal_depth = image::Image(100, 100);
  try {
    r.render_octahedral(imp, {}, render::RenderOptions{});
    FAIL();
  } catch (const render::RenderError& e) {
    EXPECT_STREQ(e.what(), "impostor maps must be 256x256 pixels, got 100x100");
  }
}

}  // namespace
}  // namespace sylva::impostor
