// Report writers. Everything here is a pure function of the Report, so the stage's outputs stay
// byte-identical for identical inputs (the engine caches them by content). No timestamps, no
// absolute paths: references are named by file name only, because the references directory's
// path is not part of the action key (its content is).
#include "stages/verify/report.h"

#include <openssl/evp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

namespace sylva::verify {

namespace {

using ojson = nlohmann::ordered_json;

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string percent(double fraction) { return fixed(fraction * 100.0, 3) + "%"; }

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// Escapes for XML/HTML text and attribute values; drops control characters XML 1.0 forbids.
std::string escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        if (c < 0x20 && ch != '\n' && ch != '\t' && ch != '\r')
          out += ' ';
        else
          out += ch;
    }
  }
  return out;
}

ojson nullable_string(const std::string& s) { return s.empty() ? ojson(nullptr) : ojson(s); }

ojson case_json(const CaseResult& c) {
  ojson j;
  j["asset"] = c.asset;
  j["view"] = c.view;
  j["status"] = status_name(c.status);
  j["message"] = c.message;
  j["image"] = nullable_string(c.image_file);
  j["reference"] = c.compared ? ojson(c.image_file) : ojson(nullptr);
  j["diff"] = nullable_string(c.diff_file);
  j["width"] = c.width;
  j["height"] = c.height;
  if (c.compared) {
    const image::CompareResult& r = c.compare;
    ojson m;
    m["size_mismatch"] = r.size_mismatch;
    m["pixels"] = r.pixels;
    m["failing_pixels"] = r.failing_pixels;
    m["failing_fraction"] = r.failing_fraction;
    m["mean_error"] = r.mean_error;
    m["rms_error"] = r.rms_error;
    m["max_error"] = r.max_error;
    m["max_pixel"] = ojson::array({r.max_x, r.max_y});
    m["psnr_db"] = std::isfinite(r.psnr) ? ojson(r.psnr) : ojson(nullptr);  // null: identical
    j["metrics"] = std::move(m);
  } else {
    j["metrics"] = nullptr;
  }
  return j;
}

const char* failure_type(CaseStatus s) {
  return s == CaseStatus::kMissingReference ? "missing_reference"
         : s == CaseStatus::kError          ? "error"
                                            : "image_mismatch";
}

// The numbers of a compared case, one per line (JUnit failure bodies).
std::string numbers_text(const CaseResult& c) {
  std::string t;
  if (!c.image_file.empty()) t += "rendering: " + c.image_file + "\n";
  if (c.compared) {
    const auto& r = c.compare;
    t += "reference: " + c.image_file + " (in the references directory)\n";
    t += "heat map: " + c.diff_file + "\n";
    if (!r.size_mismatch) {
      t += "failing pixels: " + std::to_string(r.failing_pixels) + " of " + std::to_string(r.pixels) + " (" +
           percent(r.failing_fraction) + ")\n";
      t += "mean error: " + fixed(r.mean_error, 6) + ", rms error: " + fixed(r.rms_error, 6) +
           ", max error: " + fixed(r.max_error, 6) + " at (" + std::to_string(r.max_x) + ", " +
           std::to_string(r.max_y) + ")\n";
      t += "PSNR: " +
           (std::isfinite(r.psnr) ? fixed(r.psnr, 2) + " dB" : std::string("infinite (identical)")) + "\n";
    }
  }
  return t;
}

std::string data_uri(const std::string& png) { return "data:image/png;base64," + base64(png); }

const char* kCss = R"css(
body{font:14px/1.4 system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:0;background:#f4f5f7;color:#1d2330}
header{padding:16px 24px;color:#fff}
header.passed{background:#1f7a3a} header.failed{background:#b3261e}
header h1{margin:0 0 4px;font-size:22px} header p{margin:0}
main{padding:16px 24px;max-width:1280px}
table{border-collapse:collapse} td,th{padding:2px 10px 2px 0;text-align:left;vertical-align:top}
th{font-weight:600;color:#4a5160}
.meta,.case,nav{background:#fff;border:1px solid #d9dce3;border-radius:6px;padding:12px 16px;margin:0 0 16px}
.case h2{font-size:16px;margin:0 0 6px}
.badge{display:inline-block;padding:1px 8px;border-radius:10px;font-size:12px;font-weight:700;color:#fff;margin-right:8px}
.badge.passed{background:#1f7a3a} .badge.failed{background:#b3261e}
.badge.missing_reference{background:#a15c00} .badge.error{background:#5b2a86}
.msg{margin:0 0 8px;font-weight:600}
.images{display:grid;grid-template-columns:repeat(3,minmax(0,1fr));gap:10px;margin:0 0 8px}
figure{margin:0} figcaption{color:#4a5160;font-size:12px}
figure img{width:100%;height:auto;image-rendering:pixelated;border:1px solid #d9dce3;background:#fff}
.none{box-sizing:border-box;display:flex;align-items:center;justify-content:center;border:1px dashed #a15c00;color:#a15c00;background:#fff7ec;text-align:center;padding:8px}
.legend{color:#4a5160;font-size:12px}
body:has(#only-failing:checked) .case.passed{display:none}
)css";

// A placeholder keeps the image's aspect ratio (width x height of the camera set).
std::string figure(const std::string& png, const std::string& caption, const std::string& missing, int width,
                   int height) {
  if (png.empty())
    return "<figure><div class=\"none\" style=\"aspect-ratio:" + std::to_string(std::max(width, 1)) + "/" +
           std::to_string(std::max(height, 1)) + "\">" + escape(missing) + "</div><figcaption>" +
           escape(caption) + "</figcaption></figure>\n";
  return "<figure><img alt=\"" + escape(caption) + "\" src=\"" + data_uri(png) + "\"><figcaption>" +
         escape(caption) + "</figcaption></figure>\n";
}

std::string counts_text(const Report& r) {
  return plural(r.count(CaseStatus::kPassed), "passed", "passed") + " · " +
         plural(r.count(CaseStatus::kFailed), "failed", "failed") + " · " +
         plural(r.count(CaseStatus::kMissingReference), "missing reference", "missing references") + " · " +
         plural(r.count(CaseStatus::kError), "error", "errors");
}

}  // namespace

std::string base64(const std::string& bytes) {
  std::string out(4 * ((bytes.size() + 2) / 3) + 1, '\0');
  const int n =
      EVP_EncodeBlock(reinterpret_cast<unsigned char*>(out.data()),
                      reinterpret_cast<const unsigned char*>(bytes.data()), static_cast<int>(bytes.size()));
  out.resize(static_cast<std::size_t>(n));
  return out;
}

std::string report_json(const Report& r) {
  ojson j;
  j["format"] = "sylva-verify-report";
  j["version"] = 1;
  j["passed"] = r.passed();
  j["summary"] = {{"cases", r.cases.size()},
                  {"passed", r.count(CaseStatus::kPassed)},
                  {"failed", r.count(CaseStatus::kFailed)},
                  {"missing_reference", r.count(CaseStatus::kMissingReference)},
                  {"error", r.count(CaseStatus::kError)}};
  j["thresholds"] = {
      {"pixel_threshold", r.thresholds.pixel_threshold},
      {"max_failing_fraction", r.thresholds.max_failing_fraction},
      {"min_psnr_db", r.thresholds.min_psnr_db > 0 ? ojson(r.thresholds.min_psnr_db) : ojson(nullptr)},
      {"compare_alpha", r.thresholds.compare_alpha}};
  j["camera_set"] = {{"width", r.width}, {"height", r.height}, {"msaa", r.msaa}, {"views", r.views}};
  j["device"] = r.device;
  j["assets"] = r.assets;
  ojson cases = ojson::array();
  for (const auto& c : r.cases) cases.push_back(case_json(c));
  j["cases"] = std::move(cases);
  j["unused_references"] = r.unused_references;
  return j.dump(2) + "\n";
}

std::string junit_xml(const Report& r) {
  auto bad = [](CaseStatus s) { return s == CaseStatus::kFailed || s == CaseStatus::kMissingReference; };
  std::size_t failures = 0, errors = 0;
  for (const auto& c : r.cases) {
    failures += bad(c.status) ? 1 : 0;
    errors += c.status == CaseStatus::kError ? 1 : 0;
  }
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += "<testsuites name=\"sylva verify\" tests=\"" + std::to_string(r.cases.size()) + "\" failures=\"" +
       std::to_string(failures) + "\" errors=\"" + std::to_string(errors) + "\">\n";
  for (const auto& asset : r.assets) {
    std::size_t n = 0, f = 0, e = 0;
    for (const auto& c : r.cases) {
      if (c.asset != asset) continue;
      ++n;
      f += bad(c.status) ? 1 : 0;
      e += c.status == CaseStatus::kError ? 1 : 0;
    }
    x += "  <testsuite name=\"verify." + escape(asset) + "\" tests=\"" + std::to_string(n) +
         "\" failures=\"" + std::to_string(f) + "\" errors=\"" + std::to_string(e) + "\" skipped=\"0\">\n";
    x += "    <properties>\n";
    x += "      <property name=\"device\" value=\"" + escape(r.device) + "\"/>\n";
    x += "      <property name=\"pixel_threshold\" value=\"" +
         escape(nlohmann::json(r.thresholds.pixel_threshold).dump()) + "\"/>\n";
    x += "      <property name=\"max_failing_fraction\" value=\"" +
         escape(nlohmann::json(r.thresholds.max_failing_fraction).dump()) + "\"/>\n";
    x += "    </properties>\n";
    for (const auto& c : r.cases) {
      if (c.asset != asset) continue;
      x += "    <testcase name=\"" + escape(c.view) + "\" classname=\"verify." + escape(asset) + "\"";
      if (c.status == CaseStatus::kPassed) {
        x += "/>\n";
        continue;
      }
      const char* tag = c.status == CaseStatus::kError ? "error" : "failure";
      x += ">\n      <" + std::string(tag) + " type=\"" + failure_type(c.status) + "\" message=\"" +
           escape(c.message) + "\">" + escape(numbers_text(c)) + "</" + tag + ">\n    </testcase>\n";
    }
    x += "  </testsuite>\n";
  }
  x += "</testsuites>\n";
  return x;
}

std::string report_html(const Report& r) {
  const bool ok = r.passed();
  std::string title = ok ? "sylva verify: passed (" + std::to_string(r.cases.size()) + " views)"
                         : "sylva verify: FAILED (" +
                               std::to_string(r.cases.size() - r.count(CaseStatus::kPassed)) + " of " +
                               std::to_string(r.cases.size()) + " views)";
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  h += "<title>" + escape(title) + "</title>\n<style>" + kCss + "</style>\n</head>\n<body>\n";
  h += std::string("<header class=\"") + (ok ? "passed" : "failed") + "\">\n<h1>" + escape(title) +
       "</h1>\n<p>" + escape(counts_text(r)) + "</p>\n</header>\n<main>\n";

  // Run parameters.
  h += "<section class=\"meta\">\n<table>\n";
  h += "<tr><th>per-pixel threshold</th><td>" + escape(fixed(r.thresholds.pixel_threshold, 4)) +
       " of full scale in any channel (" + escape(fixed(r.thresholds.pixel_threshold * 255.0, 1)) +
       " of 255 levels)</td></tr>\n";
  h += "<tr><th>allowed failing pixels</th><td>" + escape(percent(r.thresholds.max_failing_fraction)) +
       "</td></tr>\n";
  h += "<tr><th>minimum PSNR</th><td>" +
       escape(r.thresholds.min_psnr_db > 0 ? fixed(r.thresholds.min_psnr_db, 2) + " dB"
                                           : std::string("not checked")) +
       "</td></tr>\n";
  h += "<tr><th>alpha compared</th><td>" + std::string(r.thresholds.compare_alpha ? "yes" : "no") +
       "</td></tr>\n";
  std::string views;
  for (const auto& v : r.views) views += (views.empty() ? "" : ", ") + v;
  h += "<tr><th>camera set</th><td>" + std::to_string(r.width) + "×" + std::to_string(r.height) + ", MSAA " +
       std::to_string(r.msaa) + "×, views: " + escape(views) + "</td></tr>\n";
  h += "<tr><th>renderer</th><td>" + escape(r.device) + "</td></tr>\n";
  if (!r.unused_references.empty()) {
    std::string unused;
    for (const auto& u : r.unused_references) unused += (unused.empty() ? "" : ", ") + u;
    h += "<tr><th>unused references</th><td>" + escape(unused) + "</td></tr>\n";
  }
  h += "</table>\n";
  h +=
      "<p class=\"legend\">Heat map: identical pixels show the reference in dim grey; differences within the "
      "threshold are dark blue; failing pixels go red → yellow → white as the difference grows to half of "
      "full "
      "scale and beyond; magenta marks pixels that exist in only one image (size mismatch).</p>\n";
  // A failed run opens on what did not pass; unticking shows everything.
  h += std::string("<label><input type=\"checkbox\" id=\"only-failing\"") + (ok ? "" : " checked") +
       "> show only views that did not pass</label>\n";
  h += "</section>\n";

  // Links to everything that did not pass.
  if (!ok && !r.cases.empty()) {
    h += "<nav>\n<strong>Did not pass</strong>\n<ul>\n";
    for (const auto& c : r.cases)
      if (c.status != CaseStatus::kPassed)
        h += "<li><a href=\"#" + escape(c.asset + "__" + c.view) + "\">" + escape(c.asset + " / " + c.view) +
             "</a>: " + escape(c.message) + "</li>\n";
    h += "</ul>\n</nav>\n";
  }

  // One section per case: reference / new / diff, then the numbers. What did not pass comes
  // first (in case order), then the rest.
  std::vector<const CaseResult*> order;
  for (const auto& c : r.cases)
    if (c.status != CaseStatus::kPassed) order.push_back(&c);
  for (const auto& c : r.cases)
    if (c.status == CaseStatus::kPassed) order.push_back(&c);
  for (const CaseResult* cp : order) {
    const CaseResult& c = *cp;
    const std::string status = status_name(c.status);
    h += "<section class=\"case " + status + "\" id=\"" + escape(c.asset + "__" + c.view) + "\">\n";
    h += "<h2><span class=\"badge " + status + "\">" + escape(status) + "</span>" +
         escape(c.asset + " / " + c.view) + "</h2>\n";
    if (!c.message.empty()) h += "<p class=\"msg\">" + escape(c.message) + "</p>\n";
    h += "<div class=\"images\">\n";
    h += figure(c.reference_png, "reference" + (c.compared ? " (" + c.image_file + ")" : std::string()),
                c.status == CaseStatus::kMissingReference ? "no reference image" : "no reference compared",
                r.width, r.height);
    h += figure(c.image_png, "new" + (c.image_file.empty() ? std::string() : " (" + c.image_file + ")"),
                "no rendering", r.width, r.height);
    h += figure(c.diff_png, "difference" + (c.diff_file.empty() ? std::string() : " (" + c.diff_file + ")"),
                "no difference image", r.width, r.height);
    h += "</div>\n";
    if (c.compared && !c.compare.size_mismatch) {
      const auto& m = c.compare;
      h += "<table class=\"numbers\">\n";
      h += "<tr><th>failing pixels</th><td>" + std::to_string(m.failing_pixels) + " of " +
           std::to_string(m.pixels) + " (" + escape(percent(m.failing_fraction)) + ")</td></tr>\n";
      h += "<tr><th>mean / rms error</th><td>" + fixed(m.mean_error, 6) + " / " + fixed(m.rms_error, 6) +
           "</td></tr>\n";
      h += "<tr><th>max error</th><td>" + fixed(m.max_error, 6) + " at (" + std::to_string(m.max_x) + ", " +
           std::to_string(m.max_y) + ")</td></tr>\n";
      h += "<tr><th>PSNR</th><td>" +
           escape(std::isfinite(m.psnr) ? fixed(m.psnr, 2) + " dB" : std::string("∞ (identical)")) +
           "</td></tr>\n";
      h += "</table>\n";
    }
    h += "</section>\n";
  }
  h += "</main>\n</body>\n</html>\n";
  return h;
}

std::string summary_line(const Report& r, std::size_t max_listed) {
  const std::size_t total = r.cases.size();
  const std::size_t bad = total - r.count(CaseStatus::kPassed);
  if (total == 0) return "nothing was verified (no assets or no views)";
  if (bad == 0) return "all " + plural(total, "view", "views") + " passed";
  std::string s =
      std::to_string(bad) + " of " + plural(total, "view", "views") + " did not pass verification: ";
  std::size_t listed = 0;
  for (const auto& c : r.cases) {
    if (c.status == CaseStatus::kPassed) continue;
    if (listed == max_listed) {
      s += "; and " + std::to_string(bad - listed) + " more";
      break;
    }
    s += std::string(listed ? "; " : "") + c.asset + "/" + c.view + ": " + c.message;
    ++listed;
  }
  return s;
}

void write_reports(const Report& report,
                   const std::function<std::filesystem::path(const std::string&)>& output_path) {
  auto write = [&](const std::string& name, const std::string& text) {
    const auto path = output_path(name);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw VerifyError(path.string() + ": error: cannot write the file");
  };
  write("report.json", report_json(report));
  write("junit.xml", junit_xml(report));
  write("report.html", report_html(report));
}

}  // namespace sylva::verify
