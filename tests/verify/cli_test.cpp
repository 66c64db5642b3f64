// `sylva render`, `sylva verify` and `sylva lodcheck` through the real binary: exit codes,
// one-line messages, the files written, the update-refs workflow on a small generate -> mesh ->
// verify recipe, and the LOD proof on a small generate -> lod recipe.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "libs/image/image_io.h"
#include "libs/render/testing/gltf_builder.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;
using render::Vec4;

struct Outcome {
  int code = -1;
  std::string out, err;
};

// Runs `env sylva args` through the shell (paths here have no spaces) and captures its output.
Outcome sylva(const test::TempDir& dir, const std::string& args, const std::string& env = "") {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  // The test recipes live in temp dirs and name the repository's presets: outside their
  // project root (docs/recipes.md), so they are run as trusted recipes.
  const std::string cmd =
      env + " " + SYLVA_BINARY + " --allow-outside-root " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  Outcome r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = test::read_file(out);
  r.err = test::read_file(err);
  return r;
}

int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

constexpr const char* kCameras =
    "version: 1\nwidth: 96\nheight: 64\nmsaa: 4\nviews:\n"
    "  - name: front\n    orbit: { azimuth_deg: 0, elevation_deg: 10 }\n"
    "  - name: side\n    orbit: { azimuth_deg: 90, elevation_deg: 10 }\n";

class RenderCli : public ::testing::Test {
 protected:
  void SetUp() override {
    render::testing::GltfBuilder b;
    const int m = b.add_material({.base_color = Vec4(0.2f, 0.6f, 0.2f, 1)});
    b.add_root(b.add_node({.mesh = b.add_mesh({render::testing::cube(1.f, m)})}));
    b.write_glb(glb_);
    test::write_file(cams_, kCameras);
  }
  test::TempDir dir_;
  fs::path glb_ = dir_ / "cube.glb";
  fs::path cams_ = dir_ / "cams.yaml";
};

// -o FILE.png: the first view (or the one --view names), one path on stdout.
TEST_F(RenderCli, OnePng) {
  const fs::path png = dir_ / "cube.png";
  Outcome r = sylva(dir_, "render " + glb_.string() + " --camera " + cams_.string() + " -o " + png.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, png.string() + "\n");
  EXPECT_NE(r.err.find("sylva: rendered 1 view of " + glb_.string() + " at 96x64 (MSAA 4x)"),
            std::string::npos)
      << r.err;
  const image::Image img = image::read_image(png);
  EXPECT_EQ(img.width(), 96);
  EXPECT_EQ(img.height(), 64);
  // The same command again writes the same bytes.
  const std::string first = test::read_file(png);
  ASSERT_EQ(
      sylva(dir_, "render " + glb_.string() + " --camera " + cams_.string() + " -o " + png.string()).code, 0);
  EXPECT_EQ(test::read_file(png), first);
  // --view picks another view: a different picture (options may come before the file).
  ASSERT_EQ(sylva(dir_, "render --view side --camera " + cams_.string() + " " + glb_.string() + " -o " +
                            png.string())
                .code,
            0);
  EXPECT_NE(test::read_file(png), first);
}

// -o DIR: one <view>.png per view, the directory created.
TEST_F(RenderCli, Directory) {
  const fs::path out = dir_ / "views" / "cube";
  const Outcome r =
      sylva(dir_, "render " + glb_.string() + " --camera " + cams_.string() + " -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, (out / "front.png").string() + "\n" + (out / "side.png").string() + "\n");
  EXPECT_TRUE(fs::exists(out / "front.png"));
  EXPECT_TRUE(fs::exists(out / "side.png"));
}

// Usage errors exit 2 with one line.
TEST_F(RenderCli, UsageErrors) {
  Outcome r = sylva(dir_, "render " + glb_.string() + " --camera " + cams_.string() + " --view top -o x.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: no view 'top' in " + cams_.string() + " (its views: front, side)\n");
  r = sylva(dir_, "render " + glb_.string() + " --camera " + cams_.string() +
                      " --view front --view side -o " + (dir_ / "x.png").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: -o " + (dir_ / "x.png").string() +
                       " is one image but 2 views were chosen; give -o a directory for several\n");
  r = sylva(dir_, "render " + glb_.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--output is required"), std::string::npos) << r.err;
  test::write_file(dir_ / "bad.yaml", "version: 1\nwidth: 0\nheight: 10\nviews: [{name: a}]\n");
  r = sylva(dir_, "render " + glb_.string() + " --camera " + (dir_ / "bad.yaml").string() + " -o x.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err.rfind(
                (dir_ / "bad.yaml").string() + ":2:8: error: 'width' must be between 1 and 16384, got 0", 0),
            0u)
      << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

// Bad input exits 1 with one line naming the file; nothing is written.
TEST_F(RenderCli, BadAssetsExitOne) {
  const fs::path png = dir_ / "x.png";
  test::write_file(dir_ / "garbage.glb", "this is not glTF");
  Outcome r = sylva(dir_, "render " + (dir_ / "garbage.glb").string() + " --camera " + cams_.string() +
                              " -o " + png.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err.rfind((dir_ / "garbage.glb").string() + ": error: invalid glTF: ", 0), 0u) << r.err;
  EXPECT_EQ(count_of(r.err, "\n"), 1) << r.err;
  r = sylva(dir_,
            "render " + (dir_ / "none.glb").string() + " --camera " + cams_.string() + " -o " + png.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, (dir_ / "none.glb").string() + ": error: No such file or directory\n");
  EXPECT_FALSE(fs::exists(png));
}

// Without any EGL vendor: exit 1 and the renderer's one-line reason.
TEST_F(RenderCli, NoEglExitsOne) {
  const Outcome r = sylva(
      dir_, "render " + glb_.string() + " --camera " + cams_.string() + " -o " + (dir_ / "x.png").string(),
      "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl.json __EGL_VENDOR_LIBRARY_DIRS=/nonexistent");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err.rfind("error: headless OpenGL is not available: ", 0), 0u) << r.err;
  EXPECT_EQ(count_of(r.err, "\n"), 1) << r.err;
}

// A small recipe: generate (young birch, 2 levels) -> mesh (no subdivision, no foliage) -> verify.
class VerifyCli : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(refs_);
    test::write_file(dir_ / "cams.yaml", kCameras);
    write_recipe("");
  }
  void write_recipe(const std::string& verify_with) {
    test::write_file(recipe_,
                     "version: 1\nname: small\nnodes:\n"
                     "  tree_birch:\n    stage: generate\n    with: { preset: " +
                         fs::absolute("configs/species/birch.yaml").string() +
                         ", age: young, texture_size: 16, levels: 2 }\n"
                         "  mesh_birch:\n    stage: mesh\n    needs: tree_birch\n"
                         "    with: { subdivision: 0, foliage: false }\n"
                         "  check:\n    stage: verify\n    needs: ['mesh_*']\n"
                         "    with: { cameras: cams.yaml, references: refs" +
                         verify_with + " }\n");
  }
  Outcome verify(const std::string& extra = "") {
    return sylva(dir_, "--out " + out_.string() + " verify " + recipe_.string() + " " + extra);
  }
  Outcome build() { return sylva(dir_, "--out " + out_.string() + " build " + recipe_.string()); }

  test::TempDir dir_;
  fs::path recipe_ = dir_ / "small.yaml";
  fs::path refs_ = dir_ / "refs";
  fs::path out_ = dir_ / "out";
  fs::path reports_ = out_ / "small" / "verify-reports" / "check";
};

// The whole workflow: no references -> fail with reports; --update-refs -> references written;
// verify and build pass; a changed reference fails both, with the stage's one-line summary.
TEST_F(VerifyCli, UpdateRefsWorkflow) {
  // 1. No references: exit 1, one FAIL line per view, reports written anyway.
  Outcome r = verify();
  ASSERT_EQ(r.code, 1) << r.err;
  EXPECT_EQ(r.out, "sylva verify: node 'check' FAILED (0/2 views passed, 2 did not pass); report: " +
                       (reports_ / "report.html").string() + "\n");
  EXPECT_NE(
      r.err.find(
          "FAIL mesh_birch/front: no reference image 'mesh_birch__front.png' in the references directory\n"),
      std::string::npos)
      << r.err;
  EXPECT_EQ(count_of(r.err, "FAIL "), 2);
  for (const char* f :
       {"report.html", "report.json", "junit.xml", "mesh_birch__front.png", "mesh_birch__side.png"})
    EXPECT_TRUE(fs::exists(reports_ / f)) << f;
  auto j = nlohmann::json::parse(test::read_file(reports_ / "report.json"));
  EXPECT_EQ(j["passed"], false);
  EXPECT_EQ(j["summary"]["missing_reference"], 2);
  EXPECT_EQ(count_of(test::read_file(reports_ / "junit.xml"), "<failure type=\"missing_reference\""), 2);
  // `sylva build` fails the verify node the same way (exit 1), publishing nothing for it.
  r = build();
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(
      r.err.find(
          "error: node 'check' (stage verify): 2 of 2 views did not pass verification: mesh_birch/front: "
          "no reference image"),
      std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(out_ / "small" / "check" / "report.html"));

  // 2. --update-refs writes the new references and exits 0.
  r = verify("--update-refs");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "sylva verify: node 'check' updated (0/2 views passed, 2 references updated in " +
                       refs_.string() + "); report: " + (reports_ / "report.html").string() + "\n");
  EXPECT_EQ(count_of(r.err, "UPDATED mesh_birch/"), 2);
  EXPECT_EQ(test::read_file(refs_ / "mesh_birch__front.png"),
            test::read_file(reports_ / "mesh_birch__front.png"));
  EXPECT_TRUE(fs::exists(refs_ / "mesh_birch__side.png"));

  // 3. Now everything passes, from the command and from the build (which publishes the reports).
  r = sylva(dir_, "--out " + out_.string() + " verify --node check --node check " + recipe_.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "sylva verify: node 'check' passed (2/2 views passed); report: " +
                       (reports_ / "report.html").string() + "\n");
  r = build();
  ASSERT_EQ(r.code, 0) << r.err;
  j = nlohmann::json::parse(test::read_file(out_ / "small" / "check" / "report.json"));
  EXPECT_EQ(j["passed"], true);
  // The stage and the command write the same report.
  EXPECT_EQ(test::read_file(out_ / "small" / "check" / "report.html"),
            test::read_file(reports_ / "report.html"));

  // 4. A reference that no longer matches (here: the other view's image) fails both.
  fs::copy_file(refs_ / "mesh_birch__side.png", refs_ / "mesh_birch__front.png",
                fs::copy_options::overwrite_existing);
  r = verify();
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("FAIL mesh_birch/front: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("% of pixels differ by more than 0.016 (allowed 1.00%)"), std::string::npos) << r.err;
  j = nlohmann::json::parse(test::read_file(reports_ / "report.json"));
  EXPECT_EQ(j["cases"][0]["status"], "failed");
  EXPECT_GT(j["cases"][0]["metrics"]["failing_fraction"].get<double>(), 0.01);
  EXPECT_EQ(build().code, 1);  // the references directory is hashed: the node re-ran

  // 5. Thresholds come from the recipe: allowing every pixel to fail lets it through.
  write_recipe(", max_failing_fraction: 1");
  EXPECT_EQ(verify().code, 0);
  EXPECT_EQ(build().code, 0);
}

// A reference for a view the camera set no longer has is pointed out, not failed.
TEST_F(VerifyCli, UnusedReferenceNote) {
  ASSERT_EQ(verify("--update-refs").code, 0);
  test::write_file(refs_ / "mesh_birch__old.png", "x");
  const Outcome r = verify();
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("note: mesh_birch__old.png in " + refs_.string() +
                       " is not used by any view of node 'check' (delete it if the view is gone)"),
            std::string::npos)
      << r.err;
}

TEST_F(VerifyCli, UsageErrors) {
  Outcome r = verify("--node nope");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: no node 'nope' of stage 'verify' in recipe 'small'\n");
  r = verify("--node mesh_birch");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: no node 'mesh_birch' of stage 'verify' in recipe 'small'\n");
  r = verify("--node chek");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("did you mean 'check'"), std::string::npos) << r.err;
  test::write_file(dir_ / "plain.yaml",
                   "version: 1\nname: plain\nnodes:\n  t:\n    stage: generate\n    with: { preset: " +
                       fs::absolute("configs/species/birch.yaml").string() + " }\n");
  r = sylva(dir_, "--out " + out_.string() + " verify " + (dir_ / "plain.yaml").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: recipe 'plain' (" + (dir_ / "plain.yaml").string() +
                       ") has no node of stage 'verify'; add one (docs/stages/verify.md)\n");
  r = sylva(dir_, "--out " + out_.string() + " verify " + (dir_ / "missing.yaml").string());
  EXPECT_EQ(r.code, 2);
}

// --report-dir puts the reports elsewhere (one folder per node).
TEST_F(VerifyCli, ReportDir) {
  const Outcome r = verify("--report-dir " + (dir_ / "reports").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(fs::exists(dir_ / "reports" / "check" / "report.html"));
  EXPECT_FALSE(fs::exists(reports_));
}

// A node whose input fails to build: exit 1, nothing verified.
TEST_F(VerifyCli, BrokenInputIsABuildFailure) {
  test::write_file(dir_ / "broken.yaml", "Levels: [");
  test::write_file(
      recipe_,
      "version: 1\nname: small\nnodes:\n  tree:\n    stage: generate\n    with: { preset: broken.yaml }\n"
      "  mesh:\n    stage: mesh\n    needs: tree\n"
      "  check:\n    stage: verify\n    needs: mesh\n    with: { cameras: cams.yaml, references: refs }\n");
  const Outcome r = verify();
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("error: node 'tree' (stage generate): "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("sylva verify: the inputs did not build"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
}

// `sylva lodcheck` on a young birch's chain at a 200-px camera: builds, renders each level at
// its switch distance against the full-detail tree, prints the table, writes lodcheck.json and
// the images, and passes; a coarse chain seen with a tighter pixel threshold fails with exit 1.
class LodcheckCli : public ::testing::Test {
 protected:
  void SetUp() override {
    test::write_file(recipe_,
                     "version: 1\nname: small\nnodes:\n"
                     "  tree_birch:\n    stage: generate\n    with: { preset: " +
                         fs::absolute("configs/species/birch.yaml").string() +
                         ", age: young, texture_size: 16 }\n"
                         "  lod_birch:\n    stage: lod\n    needs: tree_birch\n"
                         "    with: { camera: { height_px: 200 }, levels: 3 }\n");
  }
  Outcome lodcheck(const std::string& extra = "") {
    return sylva(dir_, "--out " + out_.string() + " lodcheck " + recipe_.string() + " " + extra);
  }
  test::TempDir dir_;
  fs::path recipe_ = dir_ / "small.yaml";
  fs::path out_ = dir_ / "out";
  fs::path report_ = out_ / "small" / "lodcheck" / "lod_birch";
};

TEST_F(LodcheckCli, PassesAndReports) {
  const Outcome r = lodcheck("--write-full " + (dir_ / "full.glb").string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_EQ(count_of(r.out, "  sylva "), 6) << r.out;  // 3 levels x 2 views
  EXPECT_NE(r.out.find("change coverage by > 0.5 and the mean coverage change is <= 0.15"), std::string::npos)
      << r.out;
  EXPECT_EQ(count_of(r.out, " ok\n"), 6) << r.out;
  EXPECT_NE(r.out.find("sylva lodcheck: node 'lod_birch' passed (6/6 views passed); report: " +
                       (report_ / "lodcheck.json").string() + "\n"),
            std::string::npos)
      << r.out;
  const auto j = nlohmann::json::parse(test::read_file(report_ / "lodcheck.json"));
  EXPECT_TRUE(j.at("passed").get<bool>());
  ASSERT_EQ(j.at("views").size(), 6u);
  double last_distance = 0;
  for (const auto& v : j.at("views")) {
    EXPECT_GT(v.at("footprint_pixels").get<std::size_t>(), 0u);
    EXPECT_GE(v.at("distance_m").get<double>(), last_distance);
    last_distance = v.at("distance_m").get<double>();
  }
  EXPECT_EQ(j.at("camera").at("height_px").get<int>(), 200);
  for (const char* f : {"full_lod0_az0.png", "sylva_lod2_az90.png", "sylva_lod2_az90_diff.png"})
    EXPECT_TRUE(fs::exists(report_ / f)) << f;
  EXPECT_EQ(image::read_image(report_ / "sylva_lod1_az0.png").height(), 200);
  EXPECT_TRUE(fs::exists(dir_ / "full.glb"));
  SYLVA_EXPECT_VALID_GLTF(dir_ / "full.glb");
}

// Issue 15: SIGTERM (as Ctrl-C) stops lodcheck between rendered views, even with --no-images,
// with exit 130 and one line; the report directory is staged beside its final place, so the
// previous complete report stays exactly as it was (here marked by a file of our own) and no
// staging directory is left behind.
TEST_F(LodcheckCli, SigtermStopsBetweenViewsAndKeepsThePreviousReport) {
  ASSERT_EQ(lodcheck("--no-images").code, 0);
  test::write_file(report_ / "marker.txt", "previous run\n");
  const std::string before = test::read_file(report_ / "lodcheck.json");
  // 24 azimuths x 3 levels: long enough that the signal lands while views are being rendered.
  std::string args = "--no-images";
  for (int a = 0; a < 360; a += 15) args += " --azimuth " + std::to_string(a);
  const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
  const std::string cmd = std::string("exec ") + SYLVA_BINARY + " --allow-outside-root --out " +
                          out_.string() + " lodcheck " + recipe_.string() + " " + args + " >" + out.string() +
                          " 2>" + err.string();
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // The staging directory appears once the build is done and the renders begin.
  auto staging = [&] {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(report_.parent_path(), ec))
      if (e.path().filename().string().rfind(".lod_birch.tmp.", 0) == 0) return true;
    return false;
  };
  int status = 0;
  bool exited = false;
  for (int i = 0; i < 6000 && !staging(); ++i) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;
      break;
    }
    ::usleep(10000);
  }
  ASSERT_FALSE(exited) << "lodcheck ended before its renders began: " << test::read_file(err);
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  for (int i = 0; i < 3000 && !exited; ++i) {  // one view renders in well under 30 s
    exited = ::waitpid(pid, &status, WNOHANG) == pid;
    if (!exited) ::usleep(10000);
  }
  if (!exited) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    FAIL() << "lodcheck did not stop within 30 s of SIGTERM";
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  EXPECT_EQ(test::read_file(err),
            "sylva lodcheck: interrupted; nothing more was written (earlier reports are as they were)\n");
  EXPECT_EQ(test::read_file(report_ / "marker.txt"), "previous run\n");
  EXPECT_EQ(test::read_file(report_ / "lodcheck.json"), before);
  EXPECT_FALSE(staging());
}

// The per-pixel threshold follows the node's pixel error delta unless given.
TEST_F(LodcheckCli, ThresholdFollowsPixelError) {
  std::string text = test::read_file(recipe_);
  text.replace(text.find("levels: 3"), 9, "levels: 1, pixel_error: 0.8");
  test::write_file(recipe_, text);
  Outcome r = lodcheck("--no-images");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(
      r.out.find("delta 0.8 px; a view passes when <= 1.00% of the tree's pixels change coverage by > 0.8"),
      std::string::npos)
      << r.out;
  r = lodcheck("--no-images --pixel-threshold 0.3");
  EXPECT_NE(r.out.find("change coverage by > 0.3"), std::string::npos) << r.out;
}

TEST_F(LodcheckCli, AnImpossibleThresholdFails) {
  const Outcome r = lodcheck("--no-images --pixel-threshold 0 --max-failing-fraction 0");
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("FAIL: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sylva lodcheck: node 'lod_birch' FAILED"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(report_ / "sylva_lod0_az0.png"));
}

TEST_F(LodcheckCli, UsageErrors) {
  Outcome r = lodcheck("--node lod_brch");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: no node 'lod_brch' of stage 'lod' in recipe 'small'; did you mean 'lod_birch'?\n");
  r = lodcheck("--node tree_birch");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: no node 'tree_birch' of stage 'lod' in recipe 'small'\n");
  r = lodcheck("--candidates " + (dir_ / "nope").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: --candidates " + (dir_ / "nope").string() + ": not a directory\n");
  test::write_file(dir_ / "plain.yaml",
                   "version: 1\nname: plain\nnodes:\n  t:\n    stage: generate\n    with: { preset: " +
                       fs::absolute("configs/species/birch.yaml").string() + " }\n");
  r = sylva(dir_, "--out " + out_.string() + " lodcheck " + (dir_ / "plain.yaml").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: recipe 'plain' (" + (dir_ / "plain.yaml").string() +
                       ") has no node of stage 'lod'; add one (docs/stages/lod.md)\n");
}

}  // namespace
}  // namespace sylva
