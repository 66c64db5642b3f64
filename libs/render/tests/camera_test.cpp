#include "libs/render/camera.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sylva::render {
namespace {

// The text of every error of a camera set, or "" when it parses.
std::string errors_of(const std::string& yaml) {
  try {
    parse_camera_set(yaml, "cams.yaml");
    return "";
  } catch (const CameraSetError& e) {
    return e.what();
  }
}

// A set with both kinds of view parses into the expected values and defaults.
TEST(CameraSet, ParsesOrbitAndLookAtViews) {
  const CameraSet set = parse_camera_set(R"(version: 1
width: 640
height: 480
fov_y_deg: 30
views:
  - name: front
    orbit: { azimuth_deg: 45, elevation_deg: 20, distance_factor: 1.5 }
  - name: close-up_1
    eye: [1, 2, 3]
    target: [0, 1, 0]
    fov_y_deg: 20
  - name: far
    orbit: { distance_m: 100 }
)",
                                         "cams.yaml");
  EXPECT_EQ(set.source, "cams.yaml");
  EXPECT_EQ(set.width, 640);
  EXPECT_EQ(set.height, 480);
  EXPECT_EQ(set.msaa, 4);
  EXPECT_EQ(set.supersample, 1);
  ASSERT_EQ(set.views.size(), 3u);
  const auto& o = std::get<OrbitView>(set.views[0].placement);
  EXPECT_EQ(set.views[0].name, "front");
  EXPECT_FLOAT_EQ(o.azimuth_deg, 45);
  EXPECT_FLOAT_EQ(o.elevation_deg, 20);
  EXPECT_FLOAT_EQ(o.distance_factor, 1.5f);
  EXPECT_FLOAT_EQ(set.views[0].fov_y_deg, 30);
  const auto& l = std::get<LookAtView>(set.views[1].placement);
  EXPECT_EQ(l.eye, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(l.target, Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(l.up, Eigen::Vector3d::UnitY());
  EXPECT_FLOAT_EQ(set.views[1].fov_y_deg, 20);
  EXPECT_FLOAT_EQ(std::get<OrbitView>(set.views[2].placement).distance_m, 100);
}

// Every problem is reported at its line and column, all at once, misspelt keys included.
// The writer: the exact text, and a read of it gives the set back (positions to 0.1 mm).
TEST(CameraSet, WritesWhatItReads) {
  CameraSet set;
  set.width = 960;
  set.height = 540;
  set.supersample = 2;
  set.fov_y_deg = 45.00000000000001;
  LookAtView walk;
  walk.eye = {1.25, 1.7, -3.00004};
  walk.target = {1.25, 1.7, -23.00004};
  set.views.push_back({"walk_0", walk, 45.f});
  LookAtView tilted = walk;
  tilted.up = {1, 0, 0};
  set.views.push_back({"tilted", tilted, 30.f});
  set.views.push_back({"side", OrbitView{90, 12.5f, 1.1f, 0}, 45.f});
  set.views.push_back({"far", OrbitView{0, 0, 1, 250}, 45.f});
  const std::string text = write_camera_set(set, "A test set.\nTwo lines.");
  EXPECT_EQ(
      text,
      "# A test set.\n# Two lines.\nversion: 1\nwidth: 960\nheight: 540\nmsaa: 4\nsupersample: 2\n"
      "fov_y_deg: 45\nviews:\n"
      "  - name: walk_0\n    eye: [1.2500, 1.7000, -3.0000]\n    target: [1.2500, 1.7000, -23.0000]\n"
      "  - name: tilted\n    eye: [1.2500, 1.7000, -3.0000]\n    target: [1.2500, 1.7000, -23.0000]\n"
      "    up: [1.0000, 0.0000, 0.0000]\n    fov_y_deg: 30\n"
      "  - name: side\n    orbit: { azimuth_deg: 90, elevation_deg: 12.5, distance_factor: 1.10000002 }\n"
      "  - name: far\n    orbit: { azimuth_deg: 0, elevation_deg: 0, distance_m: 250 }\n");
  const CameraSet back = parse_camera_set(text, "back.yaml");
  EXPECT_EQ(back.width, 960);
  EXPECT_EQ(back.supersample, 2);
  EXPECT_EQ(back.fov_y_deg, 45.0);
  ASSERT_EQ(back.views.size(), 4u);
  EXPECT_EQ(std::get<LookAtView>(back.views[0].placement).eye, Eigen::Vector3d(1.25, 1.7, -3));
  EXPECT_EQ(std::get<LookAtView>(back.views[1].placement).up, Eigen::Vector3d::UnitX());
  EXPECT_EQ(back.views[1].fov_y_deg, 30.f);
  EXPECT_EQ(back.views[2].fov_y_deg, 45.f);
  EXPECT_EQ(std::get<OrbitView>(back.views[2].placement).distance_factor, 1.1f);
  EXPECT_EQ(std::get<OrbitView>(back.views[3].placement).distance_m, 250.f);
  EXPECT_EQ(write_camera_set(parse_camera_set(write_camera_set(back), "x.yaml")), write_camera_set(back));
  // Without supersampling and a comment: neither line.
  set.supersample = 1;
  EXPECT_EQ(write_camera_set(set).rfind("version: 1\nwidth: 960\nheight: 540\nmsaa: 4\nfov_y_deg: 45\n", 0),
            0u);
}

TEST(CameraSet, ErrorsCarryPositionsAndAreCollected) {
  EXPECT_EQ(
      errors_of(R"(version: 1
width: 64
height: 0
msaa: 3
views:
  - name: front
    orbit: { azimuth: 10 }
  - name: top
    eye: [0, 1]
    target: [0, 0, 0]
)"),
      "cams.yaml:3:9: error: 'height' must be between 1 and 16384, got 0\n"
      "cams.yaml:4:7: error: 'msaa' must be 1 (off), 2, 4, 8 or 16, got 3\n"
      "cams.yaml:7:14: error: unknown key 'azimuth' in orbit of view 'front'; did you mean 'azimuth_deg'?\n"
      "cams.yaml:9:10: error: 'eye' in view 'top' must be a list of three numbers [x, y, z]");
}

// `supersample` k draws k x the size and averages k x k blocks (RenderOptions::supersample).
TEST(CameraSet, Supersample) {
  const CameraSet set = parse_camera_set(
      "version: 1\nwidth: 64\nheight: 32\nmsaa: 4\nsupersample: 2\n"
      "views:\n  - name: a\n    orbit: {}\n",
      "cams.yaml");
  EXPECT_EQ(set.supersample, 2);
  EXPECT_EQ(
      errors_of("version: 1\nwidth: 64\nheight: 32\nsupersample: 5\nviews:\n  - name: a\n    orbit: {}\n"),
      "cams.yaml:4:14: error: 'supersample' must be 1 (off), 2, 3 or 4, got 5");
}

TEST(CameraSet, StructuralErrors) {
  EXPECT_EQ(errors_of("version: 1\nwidth: 8\nheight: 8\nview: []\n"),
            "cams.yaml:4:1: error: unknown key 'view' in camera set; did you mean 'views'?\n"
            "cams.yaml:1:1: error: missing key 'views'");
  EXPECT_EQ(errors_of("version: 2\nwidth: 8\nheight: 8\nviews: []\n"),
            "cams.yaml:1:10: error: unsupported camera set version 2 (must be 1)\n"
            "cams.yaml:4:8: error: 'views' must be a non-empty list");
  EXPECT_EQ(errors_of("version: 1\nwidth: 8\nheight: 8\nviews:\n  - name: a\n  - name: a b\n    orbit: {}\n"),
            "cams.yaml:5:5: error: view 'a' needs either 'orbit' or 'eye' and 'target'\n"
            "cams.yaml:6:11: error: view name must match [A-Za-z0-9_.-]+");
  EXPECT_EQ(errors_of("version: 1\nwidth: 8\nheight: 8\nviews:\n"
                      "  - {name: a, orbit: {elevation_deg: 95}}\n"
                      "  - {name: b, eye: [0, 0, 1], target: [0, 0, 1]}\n"
                      "  - {name: c, eye: [0, 5, 0], target: [0, 0, 0]}\n"
                      "  - {name: c, orbit: {}, fov_y_deg: 180}\n"),
            "cams.yaml:5:38: error: 'elevation_deg' must be between -90 and 90\n"
            "cams.yaml:6:20: error: view 'b': 'eye' and 'target' are the same point\n"
            "cams.yaml:7:20: error: view 'c': 'up' is parallel to the viewing direction\n"
            "cams.yaml:8:37: error: 'fov_y_deg' must be between 0 and 180 degrees (exclusive)");
  EXPECT_EQ(
      errors_of(
          "version: 1\nwidth: 8\nheight: 8\nviews:\n  - {name: a, orbit: {}}\n  - {name: a, orbit: {}}\n"),
      "cams.yaml:6:12: error: duplicate view name 'a'");
}

// YAML syntax errors and unreadable files get the same file:line:col form.
TEST(CameraSet, SyntaxErrorAndMissingFile) {
  const std::string e = errors_of("version: 1\nviews: [a, b\n");
  EXPECT_EQ(e.rfind("cams.yaml:", 0), 0u) << e;
  EXPECT_NE(e.find(": error: "), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  try {
    load_camera_set("no/such/cameras.yaml");
    FAIL();
  } catch (const CameraSetError& err) {
    EXPECT_STREQ(err.what(), "no/such/cameras.yaml: error: No such file or directory");
  }
  EXPECT_EQ(errors_of(""), "cams.yaml:1:1: error: camera set is empty");
}

// The shipped sets are valid.
TEST(CameraSet, ShippedSetsLoad) {
  for (const char* name : {"default", "verify", "turntable"}) {
    const CameraSet set = load_camera_set(std::string("configs/cameras/") + name + ".yaml");
    EXPECT_FALSE(set.views.empty()) << name;
  }
  EXPECT_EQ(load_camera_set("configs/cameras/default.yaml").views.size(), 4u);
}

Bounds box(const Vec3& lo, const Vec3& hi) {
  Bounds b;
  b.extend(lo);
  b.extend(hi);
  return b;
}

// Orbit views: azimuth 0 looks from +Z, 90 from +X; distance factor 1 fits the bounding sphere
// in the narrower half field of view; clip planes enclose the sphere.
TEST(Resolve, OrbitGeometry) {
  const Bounds b = box(Vec3(-1, 0, -1), Vec3(1, 2, 1));  // centre (0,1,0), radius sqrt(3)
  const float r = std::sqrt(3.f);
  CameraView v;
  v.fov_y_deg = 60;
  v.placement = OrbitView{0, 0, 1, 0};
  Camera c = resolve(v, b, 1.f);
  EXPECT_TRUE(c.target.isApprox(Vec3(0, 1, 0)));
  EXPECT_NEAR(c.eye.x(), 0, 1e-5);
  EXPECT_NEAR(c.eye.z(), r / std::sin(30.f * 3.14159265f / 180.f), 1e-4);  // 2 r
  EXPECT_LE(c.z_near, 2 * r - r);
  EXPECT_GE(c.z_far, 2 * r + r);

  v.placement = OrbitView{90, 0, 2, 0};
  c = resolve(v, b, 1.f);
  EXPECT_NEAR(c.eye.x(), 4 * r, 1e-4);
  EXPECT_NEAR(c.eye.z(), 0, 1e-4);

  // A wide image: the vertical fov is the narrower one; a tall image fits the horizontal.
  v.placement = OrbitView{0, 0, 1, 0};
  const float tall = resolve(v, b, 0.5f).eye.z() - 0.f;
  EXPECT_GT(tall, resolve(v, b, 2.f).eye.z());

  // Straight down: the image's top points to -Z (the far side seen from the front).
  v.placement = OrbitView{0, 90, 1, 0};
  c = resolve(v, b, 1.f);
  EXPECT_NEAR(c.eye.y(), 1 + 2 * r, 1e-4);
  EXPECT_TRUE(c.up.isApprox(Vec3(0, 0, -1)));

  // distance_m overrides the factor.
  v.placement = OrbitView{0, 0, 1, 25};
  EXPECT_NEAR(resolve(v, b, 1.f).eye.z(), 25, 1e-4);
}

// The projection puts the target at the image centre and the bounding sphere's top at the
// edge of the frame when the distance factor is 1.
TEST(Resolve, ProjectionFitsSphere) {
  const Bounds b = box(Vec3(-1, -1, -1), Vec3(1, 1, 1));
  CameraView v;
  v.fov_y_deg = 40;
  v.placement = OrbitView{30, 20, 1, 0};
  const Camera c = resolve(v, b, 1.f);
  const Mat4 vp = c.projection_matrix(1.f) * c.view_matrix();
  const Vec4 centre = vp * Vec4(0, 0, 0, 1);
  EXPECT_NEAR(centre.x() / centre.w(), 0, 1e-5);
  EXPECT_NEAR(centre.y() / centre.w(), 0, 1e-5);
  // The sphere's silhouette touches the frame: the tangent ray makes the half-fov angle.
  const float d = (c.eye - c.target).norm();
  EXPECT_NEAR(std::asin(std::sqrt(3.f) / d), 20.f * 3.14159265f / 180.f, 1e-4);
  // Everything inside the box is between the clip planes.
  for (int i = 0; i < 8; ++i) {
    const Vec3 corner((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    const Vec4 p = vp * corner.homogeneous();
    EXPECT_GT(p.z() / p.w(), -1.f);
    EXPECT_LT(p.z() / p.w(), 1.f);
  }
}

// Look-at views pass through; an empty scene is treated as a unit box at the origin.
TEST(Resolve, LookAtAndEmptyScene) {
  CameraView v;
  v.name = "x";
  v.placement = LookAtView{Eigen::Vector3d(0, 1, 5), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d::UnitY()};
  const Camera c = resolve(v, Bounds(), 1.f);
  EXPECT_EQ(c.name, "x");
  EXPECT_EQ(c.eye, Vec3(0, 1, 5));
  EXPECT_GT(c.z_near, 0);
  EXPECT_GT(c.z_far, 5.f);
}

}  // namespace
}  // namespace sylva::render
