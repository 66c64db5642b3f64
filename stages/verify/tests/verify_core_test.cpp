// The verification core with a fake renderer: verdicts, file names, missing and unreadable
// references, broken assets, unused references. The fake draws a 30 px square that moves one
// pixel per metre of the asset's x translation, so failing fractions are exact.
#include "stages/verify/verify_core.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "libs/image/image_io.h"
#include "stages/verify/tests/fake_renderer.h"
#include "tests/support/test_support.h"

namespace sylva::verify {
namespace {

namespace fs = std::filesystem;
using testing::FakeRenderer;

std::set<std::string> files_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

class VerifyCoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(refs_);
    fs::create_directories(out_);
  }
  // Runs the core on `assets` with the fake renderer, writing into out_ (emptied first).
  Report run(const std::vector<Asset>& assets, const Thresholds& t = {},
             const render::CameraSet& cams = testing::small_camera_set()) {
    fs::remove_all(out_);
    fs::create_directories(out_);
    const RunEnv env{renderer_, [&](const std::string& name) { return out_ / name; }, {}};
    return run_verification(assets, cams, refs_, t, env);
  }
  // Makes the current outputs the references.
  void accept() {
    for (const auto& name : files_in(out_))
      if (name.find(".diff.") == std::string::npos)
        fs::copy_file(out_ / name, refs_ / name, fs::copy_options::overwrite_existing);
  }
  fs::path glb(const std::string& name, float tx) {
    const fs::path p = dir_ / (name + ".glb");
    testing::write_square_glb(p, tx);
    return p;
  }

  sylva::test::TempDir dir_;
  fs::path refs_ = dir_ / "refs";
  fs::path out_ = dir_ / "out";
  FakeRenderer renderer_;
};

// Identical images: pass, PSNR infinite, zero errors.
TEST(JudgeView, IdenticalPasses) {
  const image::Image a(20, 10, {1, 2, 3, 255});
  const CaseResult c = judge_view("oak", "front", &a, a, {});
  EXPECT_EQ(c.status, CaseStatus::kPassed);
  EXPECT_EQ(c.message, "");
  EXPECT_EQ(c.image_file, "oak__front.png");
  EXPECT_EQ(c.diff_file, "oak__front.diff.png");
  EXPECT_TRUE(c.compared);
  EXPECT_EQ(c.compare.failing_pixels, 0u);
  EXPECT_TRUE(std::isinf(c.compare.psnr));
  EXPECT_EQ(c.width, 20);
  EXPECT_EQ(c.height, 10);
}

// No reference: its own status and a message naming the expected file; nothing compared.
TEST(JudgeView, MissingReference) {
  const image::Image a(4, 4);
  const CaseResult c = judge_view("oak", "top", nullptr, a, {});
  EXPECT_EQ(c.status, CaseStatus::kMissingReference);
  EXPECT_EQ(c.message, "no reference image 'oak__top.png' in the references directory");
  EXPECT_FALSE(c.compared);
  EXPECT_EQ(c.diff_file, "");
}

// A size mismatch fails with the library's sentence.
TEST(JudgeView, SizeMismatchFails) {
  const image::Image a(4, 4), b(8, 4);
  const CaseResult c = judge_view("oak", "top", &a, b, {});
  EXPECT_EQ(c.status, CaseStatus::kFailed);
  EXPECT_EQ(c.message, "size mismatch: reference 4x4, test 8x4");
}

// The optional PSNR floor fails a view whose pixels are all within the per-pixel threshold.
TEST(JudgeView, PsnrFloor) {
  const image::Image a(10, 10, {100, 100, 100, 255}), b(10, 10, {103, 100, 100, 255});  // 3/255 < 0.016
  Thresholds t;
  EXPECT_EQ(judge_view("a", "v", &a, b, t).status, CaseStatus::kPassed);
  t.min_psnr_db = 50;  // rms over 4 channels = 1.5/255 -> 44.6 dB
  const CaseResult c = judge_view("a", "v", &a, b, t);
  EXPECT_EQ(c.status, CaseStatus::kFailed);
  EXPECT_EQ(c.message, "PSNR 44.61 dB is below the minimum 50.00 dB");
  t.min_psnr_db = 40;
  EXPECT_EQ(judge_view("a", "v", &a, b, t).status, CaseStatus::kPassed);
}

// Same scene twice: every view passes; outputs are exactly the renderings and heat maps.
TEST_F(VerifyCoreTest, UnchangedScenePasses) {
  const std::vector<Asset> assets{{"oak", glb("oak", 0)}, {"birch", glb("birch", 20)}};
  run(assets);
  accept();
  const Report r = run(assets);
  EXPECT_TRUE(r.passed());
  ASSERT_EQ(r.cases.size(), 4u);
  EXPECT_EQ(r.cases[0].asset, "oak");
  EXPECT_EQ(r.cases[0].view, "front");
  EXPECT_EQ(r.cases[3].asset, "birch");
  EXPECT_EQ(r.cases[3].view, "side");
  EXPECT_EQ(r.device, "fake renderer (tests)");
  EXPECT_EQ(r.views, (std::vector<std::string>{"front", "side"}));
  EXPECT_EQ(r.width, 100);
  EXPECT_EQ(r.msaa, 1);
  EXPECT_EQ(files_in(out_),
            (std::set<std::string>{"birch__front.diff.png", "birch__front.png", "birch__side.diff.png",
                                   "birch__side.png", "oak__front.diff.png", "oak__front.png",
                                   "oak__side.diff.png", "oak__side.png"}));
  // One upload (render_views call) per asset, every view in it.
  EXPECT_EQ(renderer_.calls, 4);
  EXPECT_EQ(renderer_.views_drawn, 8);
  // PNG bytes are kept for the HTML report and equal the files written.
  EXPECT_EQ(r.cases[0].image_png, sylva::test::read_file(out_ / "oak__front.png"));
  EXPECT_EQ(r.cases[0].reference_png, sylva::test::read_file(refs_ / "oak__front.png"));
  EXPECT_EQ(r.cases[0].diff_png, sylva::test::read_file(out_ / "oak__front.diff.png"));
}

// A shifted object fails with the expected failing fraction: a 30 px square moved by 4 px
// changes 2 * 4 * 30 = 240 of 10,000 pixels (2.4 % > 1 %); moved by 1 px, 60 pixels (0.6 %) pass.
TEST_F(VerifyCoreTest, ShiftedSceneFailsWithExpectedFraction) {
  run({{"oak", glb("oak", 0)}});
  accept();
  Report r = run({{"oak", glb("oak4", 4)}});
  ASSERT_EQ(r.cases.size(), 2u);
  for (const auto& c : r.cases) {
    EXPECT_EQ(c.status, CaseStatus::kFailed);
    EXPECT_EQ(c.compare.failing_pixels, 240u);
    EXPECT_DOUBLE_EQ(c.compare.failing_fraction, 0.024);
    EXPECT_EQ(c.message, "2.40% of pixels differ by more than 0.016 (allowed 1.00%)");
  }
  EXPECT_FALSE(r.passed());
  EXPECT_EQ(r.count(CaseStatus::kFailed), 2u);

  r = run({{"oak", glb("oak1", 1)}});
  for (const auto& c : r.cases) {
    EXPECT_EQ(c.status, CaseStatus::kPassed);
    EXPECT_EQ(c.compare.failing_pixels, 60u);
  }
  EXPECT_TRUE(r.passed());

  // A recipe may allow more: 3 % lets the 4 px shift through.
  Thresholds loose;
  loose.max_failing_fraction = 0.03;
  EXPECT_TRUE(run({{"oak", glb("oak4", 4)}}, loose).passed());
}

// One missing reference is one failing case with its own status; the others still compare, and
// no heat map is written for the missing one.
TEST_F(VerifyCoreTest, MissingReferenceIsAFailingCase) {
  run({{"oak", glb("oak", 0)}});
  accept();
  fs::remove(refs_ / "oak__side.png");
  const Report r = run({{"oak", glb("oak", 0)}});
  EXPECT_FALSE(r.passed());
  ASSERT_EQ(r.cases.size(), 2u);
  EXPECT_EQ(r.cases[0].status, CaseStatus::kPassed);
  EXPECT_EQ(r.cases[1].status, CaseStatus::kMissingReference);
  EXPECT_EQ(r.cases[1].message, "no reference image 'oak__side.png' in the references directory");
  EXPECT_FALSE(fs::exists(out_ / "oak__side.diff.png"));
  EXPECT_TRUE(fs::exists(out_ / "oak__side.png"));  // the new image, ready to be accepted
  EXPECT_FALSE(r.cases[1].image_png.empty());
  EXPECT_TRUE(r.cases[1].reference_png.empty());
}

// An empty references directory: every case is missing, none is an error.
TEST_F(VerifyCoreTest, NoReferencesAtAll) {
  const Report r = run({{"oak", glb("oak", 0)}});
  EXPECT_EQ(r.count(CaseStatus::kMissingReference), 2u);
  EXPECT_FALSE(r.passed());
}

// A broken GLB gives an error case per view naming the file; the other asset is still verified.
TEST_F(VerifyCoreTest, BrokenAssetIsReportedNotFatal) {
  run({{"oak", glb("oak", 0)}});
  accept();
  sylva::test::write_file(dir_ / "broken.glb", "glTF but not really");
  const Report r = run({{"broken", dir_ / "broken.glb"}, {"oak", glb("oak", 0)}});
  ASSERT_EQ(r.cases.size(), 4u);
  for (int i : {0, 1}) {
    EXPECT_EQ(r.cases[i].status, CaseStatus::kError);
    EXPECT_NE(r.cases[i].message.find((dir_ / "broken.glb").string() + ": error: "), std::string::npos)
        << r.cases[i].message;
    EXPECT_EQ(r.cases[i].image_file, "");
  }
  EXPECT_EQ(r.cases[2].status, CaseStatus::kPassed);
  EXPECT_EQ(r.count(CaseStatus::kError), 2u);
  EXPECT_FALSE(fs::exists(out_ / "broken__front.png"));
}

// A reference that is not an image is an error case (and the rendering is still written).
TEST_F(VerifyCoreTest, UnreadableReference) {
  sylva::test::write_file(refs_ / "oak__front.png", "not a png");
  const Report r = run({{"oak", glb("oak", 0)}});
  EXPECT_EQ(r.cases[0].status, CaseStatus::kError);
  EXPECT_EQ(r.cases[0].message.rfind(
                "the reference image cannot be read: " + (refs_ / "oak__front.png").string(), 0),
            0u)
      << r.cases[0].message;
  EXPECT_TRUE(fs::exists(out_ / "oak__front.png"));
  EXPECT_EQ(r.cases[1].status, CaseStatus::kMissingReference);
}

// A different colour (a texture or lighting change) fails every pixel of the square.
TEST_F(VerifyCoreTest, ColourChangeFails) {
  run({{"oak", glb("oak", 0)}});
  accept();
  testing::write_square_glb(dir_ / "oak_red.glb", 0, 0.9f, 0.2f, 0.1f);
  const Report r = run({{"oak", dir_ / "oak_red.glb"}});
  EXPECT_EQ(r.cases[0].status, CaseStatus::kFailed);
  EXPECT_EQ(r.cases[0].compare.failing_pixels, 900u);
}

// Names become file names: they must be valid and distinct.
TEST_F(VerifyCoreTest, AssetNamesAreChecked) {
  const fs::path f = glb("oak", 0);
  EXPECT_THROW(run({{"oak", f}, {"oak", f}}), VerifyError);
  EXPECT_THROW(run({{"../oak", f}}), VerifyError);
  EXPECT_THROW(run({{"", f}}), VerifyError);
}

// References of this run's assets for views the camera set no longer has are listed; heat maps,
// other assets' files and current references are not.
TEST_F(VerifyCoreTest, UnusedReferencesAreListed) {
  run({{"oak", glb("oak", 0)}});
  accept();
  for (const char* name : {"oak__old.png", "oak__old.diff.png", "pine__front.png", "oak__notes.txt"})
    sylva::test::write_file(refs_ / name, "x");
  const Report r = run({{"oak", glb("oak", 0)}});
  EXPECT_TRUE(r.passed());
  EXPECT_EQ(r.unused_references, (std::vector<std::string>{"oak__old.png"}));
}

// Ctrl-C: the cancellation hook is consulted and its exception passes through.
TEST_F(VerifyCoreTest, CancellationPropagates) {
  struct Stop {};
  const RunEnv env{renderer_, [&](const std::string& name) { return out_ / name; }, [] { throw Stop{}; }};
  EXPECT_THROW(run_verification({{"oak", glb("oak", 0)}}, testing::small_camera_set(), refs_, {}, env), Stop);
}

// An output that cannot be written stops the run with the path in the message.
TEST_F(VerifyCoreTest, UnwritableOutput) {
  const RunEnv env{renderer_, [&](const std::string& name) { return dir_ / "no" / "such" / name; }, {}};
  try {
    run_verification({{"oak", glb("oak", 0)}}, testing::small_camera_set(), refs_, {}, env);
    FAIL() << "no exception";
  } catch (const VerifyError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir_ / "no" / "such" / "oak__front.png").string() + ": error: cannot write the file");
  }
}

}  // namespace
}  // namespace sylva::verify
