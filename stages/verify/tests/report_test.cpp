// The report files parse and agree with the Report: report.json (nlohmann_json), junit.xml and
// report.html (a small well-formedness checker: balanced tags, quoted attributes, known
// entities), and they are deterministic.
#include "stages/verify/report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <vector>

#include "libs/image/image_io.h"

namespace sylva::verify {
namespace {

// Tag structure of an XML/HTML text. Checks that every element closes in order (HTML void
// elements and self-closing tags excepted), attribute values are quoted, and '&' only starts a
// known entity. Returns "" when well formed, else what is wrong; counts start tags by name.
std::string check_markup(const std::string& text, bool html, std::map<std::string, int>* counts) {
  static const std::vector<std::string> kVoid{"meta", "img", "input", "br", "hr", "link"};
  std::vector<std::string> stack;
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == '&') {
      static const std::regex entity("^&(amp|lt|gt|quot|#39);");
      if (!std::regex_search(text.substr(i, 8), entity)) return "bad entity at " + std::to_string(i);
      ++i;
      continue;
    }
    if (text[i] != '<') {
      ++i;
      continue;
    }
    const std::size_t end = text.find('>', i);
    if (end == std::string::npos) return "unterminated tag at " + std::to_string(i);
    std::string tag = text.substr(i + 1, end - i - 1);
    i = end + 1;
    if (tag.starts_with("?") || tag.starts_with("!")) continue;  // <?xml ...?>, <!DOCTYPE html>
    if (tag.starts_with("/")) {
      const std::string name = tag.substr(1);
      if (stack.empty() || stack.back() != name)
        return "</" + name + "> closes <" + (stack.empty() ? std::string("nothing") : stack.back()) + ">";
      stack.pop_back();
      continue;
    }
    const bool self_closing = tag.ends_with("/");
    if (self_closing) tag.pop_back();
    const std::string name = tag.substr(0, tag.find_first_of(" \n"));
    // Attributes: name="value" pairs (values without '<' or '"' inside) or bare names (HTML).
    static const std::regex attrs(R"(^[A-Za-z][A-Za-z0-9:-]*(\s+[A-Za-z-]+(="[^"<]*")?)*\s*$)");
    if (!std::regex_match(tag, attrs)) return "malformed tag <" + tag.substr(0, 60) + ">";
    if (counts) ++(*counts)[name];
    const bool is_void = html && std::find(kVoid.begin(), kVoid.end(), name) != kVoid.end();
    if (!self_closing && !is_void) stack.push_back(name);
  }
  if (!stack.empty()) return "<" + stack.back() + "> is never closed";
  return "";
}

int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

std::string png(const image::Image& img) {
  const auto bytes = image::encode_png(img);
  return std::string(bytes.begin(), bytes.end());
}

// Four cases, one of each status, with real PNG bytes.
Report sample_report() {
  Report r;
  r.device = "llvmpipe <test> & co";
  r.width = r.height = 8;
  r.msaa = 4;
  r.views = {"front", "side"};
  r.assets = {"mesh_oak", "mesh_birch"};
  const image::Image ref(8, 8, {10, 20, 30, 255});
  image::Image moved = ref;
  for (int x = 0; x < 8; ++x) moved.set(x, 0, {250, 20, 30, 255});
  const std::string ref_png = png(ref), moved_png = png(moved);

  CaseResult pass = judge_view("mesh_oak", "front", &ref, ref, r.thresholds);
  pass.reference_png = pass.image_png = pass.diff_png = ref_png;
  CaseResult fail = judge_view("mesh_oak", "side", &ref, moved, r.thresholds);
  fail.reference_png = ref_png;
  fail.image_png = moved_png;
  fail.diff_png = png(image::diff_heatmap(ref, moved));
  CaseResult missing = judge_view("mesh_birch", "front", nullptr, ref, r.thresholds);
  missing.image_png = ref_png;
  CaseResult error;
  error.asset = "mesh_birch";
  error.view = "side";
  error.status = CaseStatus::kError;
  error.message = "out/x/tree.glb: error: invalid glTF: \"<bad>\" & \x01 worse";
  r.cases = {pass, fail, missing, error};
  r.unused_references = {"mesh_oak__old.png"};
  return r;
}

// report.json: every number and status, PSNR null when identical, metrics null without a reference.
TEST(ReportJson, ParsesAndAgrees) {
  const Report r = sample_report();
  const auto j = nlohmann::json::parse(report_json(r));
  EXPECT_EQ(j["format"], "sylva-verify-report");
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["passed"], false);
  EXPECT_EQ(j["summary"]["cases"], 4);
  EXPECT_EQ(j["summary"]["passed"], 1);
  EXPECT_EQ(j["summary"]["failed"], 1);
  EXPECT_EQ(j["summary"]["missing_reference"], 1);
  EXPECT_EQ(j["summary"]["error"], 1);
  EXPECT_EQ(j["thresholds"]["pixel_threshold"], 0.016);
  EXPECT_EQ(j["thresholds"]["max_failing_fraction"], 0.01);
  EXPECT_TRUE(j["thresholds"]["min_psnr_db"].is_null());
  EXPECT_EQ(j["camera_set"]["views"], nlohmann::json({"front", "side"}));
  EXPECT_EQ(j["camera_set"]["msaa"], 4);
  EXPECT_EQ(j["device"], "llvmpipe <test> & co");
  EXPECT_EQ(j["assets"], nlohmann::json({"mesh_oak", "mesh_birch"}));
  ASSERT_EQ(j["cases"].size(), 4u);
  const auto& pass = j["cases"][0];
  EXPECT_EQ(pass["status"], "passed");
  EXPECT_EQ(pass["image"], "mesh_oak__front.png");
  EXPECT_EQ(pass["reference"], "mesh_oak__front.png");
  EXPECT_EQ(pass["diff"], "mesh_oak__front.diff.png");
  EXPECT_TRUE(pass["metrics"]["psnr_db"].is_null());
  EXPECT_EQ(pass["metrics"]["failing_pixels"], 0);
  const auto& fail = j["cases"][1];
  EXPECT_EQ(fail["status"], "failed");
  EXPECT_EQ(fail["metrics"]["failing_pixels"], 8);
  EXPECT_EQ(fail["metrics"]["pixels"], 64);
  EXPECT_DOUBLE_EQ(fail["metrics"]["failing_fraction"].get<double>(), 0.125);
  EXPECT_NEAR(fail["metrics"]["max_error"].get<double>(), 240.0 / 255.0, 1e-6);
  EXPECT_EQ(fail["metrics"]["max_pixel"], nlohmann::json({0, 0}));
  EXPECT_GT(fail["metrics"]["psnr_db"].get<double>(), 0);
  EXPECT_EQ(fail["message"], "12.50% of pixels differ by more than 0.016 (allowed 1.00%)");
  const auto& missing = j["cases"][2];
  EXPECT_EQ(missing["status"], "missing_reference");
  EXPECT_TRUE(missing["metrics"].is_null());
  EXPECT_TRUE(missing["reference"].is_null());
  EXPECT_TRUE(missing["diff"].is_null());
  EXPECT_EQ(missing["image"], "mesh_birch__front.png");
  EXPECT_EQ(j["cases"][3]["status"], "error");
  EXPECT_TRUE(j["cases"][3]["image"].is_null());
  EXPECT_EQ(j["unused_references"], nlohmann::json({"mesh_oak__old.png"}));
}

// junit.xml: well formed; one testsuite per asset, one testcase per view; failures for mismatches
// and missing references, errors for unreadable assets; counts in the attributes.
TEST(JunitXml, StructureAndCounts) {
  const std::string x = junit_xml(sample_report());
  std::map<std::string, int> tags;
  EXPECT_EQ(check_markup(x, false, &tags), "");
  EXPECT_TRUE(x.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites "));
  EXPECT_EQ(tags["testsuites"], 1);
  EXPECT_EQ(tags["testsuite"], 2);
  EXPECT_EQ(tags["testcase"], 4);
  EXPECT_EQ(tags["failure"], 2);
  EXPECT_EQ(tags["error"], 1);
  EXPECT_NE(x.find("<testsuites name=\"sylva verify\" tests=\"4\" failures=\"2\" errors=\"1\">"),
            std::string::npos);
  EXPECT_NE(
      x.find("<testsuite name=\"verify.mesh_oak\" tests=\"2\" failures=\"1\" errors=\"0\" skipped=\"0\">"),
      std::string::npos);
  EXPECT_NE(x.find("<testcase name=\"front\" classname=\"verify.mesh_oak\"/>"), std::string::npos);
  EXPECT_NE(
      x.find(
          "<failure type=\"missing_reference\" message=\"no reference image &#39;mesh_birch__front.png&#39; "
          "in the references directory\">"),
      std::string::npos);
  EXPECT_NE(x.find("<failure type=\"image_mismatch\" message=\"12.50% of pixels"), std::string::npos);
  // Text from outside (tinygltf messages) is escaped; control characters are dropped.
  EXPECT_NE(x.find("invalid glTF: &quot;&lt;bad&gt;&quot; &amp;   worse"), std::string::npos);
  EXPECT_NE(x.find("<property name=\"device\" value=\"llvmpipe &lt;test&gt; &amp; co\"/>"),
            std::string::npos);
}

// report.html: well formed; one section per case with reference / new / diff figures; images are
// data URIs whose base64 decodes to the PNG bytes; missing images are named, not broken.
TEST(ReportHtml, SelfContainedAndComplete) {
  const Report r = sample_report();
  const std::string h = report_html(r);
  std::map<std::string, int> tags;
  EXPECT_EQ(check_markup(h, true, &tags), "");
  EXPECT_TRUE(h.starts_with("<!DOCTYPE html>\n<html lang=\"en\">"));
  EXPECT_EQ(tags["section"], 5);  // the run parameters + 4 cases
  EXPECT_EQ(count_of(h, "<section class=\"case "), 4);
  EXPECT_EQ(count_of(h, "<section class=\"case passed\" id=\"mesh_oak__front\">"), 1);
  EXPECT_EQ(tags["figure"], 12);  // 3 per case
  // pass: 3 images, fail: 3, missing: the new one only, error: none.
  EXPECT_EQ(tags["img"], 7);
  EXPECT_EQ(count_of(h, "src=\"data:image/png;base64,"), 7);
  EXPECT_EQ(count_of(h, "<div class=\"none\" style=\"aspect-ratio:8/8\">no reference image</div>"), 1);
  EXPECT_NE(h.find("<title>sylva verify: FAILED (3 of 4 views)</title>"), std::string::npos);
  EXPECT_NE(h.find("1 passed · 1 failed · 1 missing reference · 1 error"), std::string::npos);
  // Nothing is loaded from elsewhere.
  EXPECT_EQ(h.find("http"), std::string::npos);
  EXPECT_EQ(h.find("<script"), std::string::npos);
  EXPECT_EQ(h.find("src=\"mesh_"), std::string::npos);
  // The first image is the first failing case's reference PNG.
  const std::string marker = "src=\"data:image/png;base64,";
  const std::size_t b = h.find(marker) + marker.size();
  EXPECT_EQ(h.substr(b, h.find('"', b) - b), base64(r.cases[1].reference_png));
  // What did not pass comes first, and the page opens showing only that.
  EXPECT_LT(h.find("<section class=\"case failed\" id=\"mesh_oak__side\">"),
            h.find("<section class=\"case passed\" id=\"mesh_oak__front\">"));
  EXPECT_NE(h.find("<input type=\"checkbox\" id=\"only-failing\" checked>"), std::string::npos);
  // The links to what did not pass.
  EXPECT_NE(h.find("<a href=\"#mesh_oak__side\">mesh_oak / side</a>"), std::string::npos);
  EXPECT_NE(h.find("mesh_oak__old.png"), std::string::npos);
}

TEST(ReportHtml, PassingRunHasNoFailureList) {
  Report r = sample_report();
  r.cases.resize(1);
  const std::string h = report_html(r);
  EXPECT_EQ(check_markup(h, true, nullptr), "");
  EXPECT_NE(h.find("<header class=\"passed\">"), std::string::npos);
  EXPECT_NE(h.find("<title>sylva verify: passed (1 views)</title>"), std::string::npos);
  EXPECT_EQ(h.find("<nav>"), std::string::npos);
  EXPECT_NE(h.find("<input type=\"checkbox\" id=\"only-failing\">"), std::string::npos);
}

// RFC 4648 test vectors.
TEST(Base64, Rfc4648) {
  EXPECT_EQ(base64(""), "");
  EXPECT_EQ(base64("f"), "Zg==");
  EXPECT_EQ(base64("fo"), "Zm8=");
  EXPECT_EQ(base64("foo"), "Zm9v");
  EXPECT_EQ(base64("foob"), "Zm9vYg==");
  EXPECT_EQ(base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(base64(std::string("\0\xff", 2)), "AP8=");
}

TEST(SummaryLine, ListsWhatDidNotPass) {
  Report r = sample_report();
  EXPECT_EQ(
      summary_line(r),
      "3 of 4 views did not pass verification: mesh_oak/side: 12.50% of pixels differ by more than 0.016 "
      "(allowed 1.00%); mesh_birch/front: no reference image 'mesh_birch__front.png' in the references "
      "directory; mesh_birch/side: out/x/tree.glb: error: invalid glTF: \"<bad>\" & \x01 worse");
  EXPECT_TRUE(summary_line(r, 1).ends_with("; and 2 more")) << summary_line(r, 1);
  r.cases.resize(1);
  EXPECT_EQ(summary_line(r), "all 1 view passed");
  r.cases.clear();
  EXPECT_EQ(summary_line(r), "nothing was verified (no assets or no views)");
}

// Same report, same bytes (the stage's outputs are cached by content).
TEST(Reports, Deterministic) {
  const Report a = sample_report(), b = sample_report();
  EXPECT_EQ(report_json(a), report_json(b));
  EXPECT_EQ(junit_xml(a), junit_xml(b));
  EXPECT_EQ(report_html(a), report_html(b));
}

// A report with no cases passes nothing.
TEST(Reports, EmptyReportIsNotAPass) {
  Report r;
  EXPECT_FALSE(r.passed());
  EXPECT_EQ(check_markup(report_html(r), true, nullptr), "");
  EXPECT_EQ(check_markup(junit_xml(r), false, nullptr), "");
}

}  // namespace
}  // namespace sylva::verify
