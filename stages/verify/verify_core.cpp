// Verification: render → read reference → compare → write images. The numbers come from
// libs/image (OpenImageIO's compare, single-threaded, so they are bit-reproducible); this file
// only decides verdicts and names files. Thresholds follow Blender's render tests; why the
// failing-pixel *fraction* (and not the per-pixel threshold) absorbs thin high-contrast edges is
// explained in libs/image/compare.h and docs/stages/verify.md.
#include "stages/verify/verify_core.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <optional>
#include <set>
#include <sstream>

#include "libs/fileio/read_file.h"
#include "libs/image/image_io.h"
#include "libs/render/forest_view.h"
#include "libs/render/gltf_scene.h"

namespace sylva::verify {

namespace fs = std::filesystem;

namespace {

bool valid_name(const std::string& s) {
  if (s.empty() || s == "." || s == "..") return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string png_bytes(const image::Image& img) {
  const std::vector<std::uint8_t> bytes = image::encode_png(img);
  return std::string(bytes.begin(), bytes.end());
}

void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw VerifyError(p.string() + ": error: cannot write the file");
}

// Files in `dir` that look like "<asset>__<view>.png" for one of `assets` but name a view that
// is not in `views` (heat maps "*.diff.png" are never references).
std::vector<std::string> unused_references(const fs::path& dir, const std::vector<std::string>& assets,
                                           const std::vector<std::string>& views) {
  std::vector<std::string> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  std::set<std::string> expected;
  for (const auto& a : assets)
    for (const auto& v : views) expected.insert(image_file_name(a, v));
  std::vector<std::string> names;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) names.push_back(it->path().filename().string());
  std::sort(names.begin(), names.end());
  for (const auto& n : names) {
    if (expected.count(n) || n.size() < 5 || n.compare(n.size() - 4, 4, ".png") != 0) continue;
    if (n.size() >= 9 && n.compare(n.size() - 9, 9, ".diff.png") == 0) continue;
    for (const auto& a : assets) {
      const std::string prefix = a + "__";
      if (n.size() > prefix.size() + 4 && n.compare(0, prefix.size(), prefix) == 0 &&
          n.find("__", prefix.size()) == std::string::npos) {
        out.push_back(n);
        break;
      }
    }
  }
  return out;
}

}  // namespace

image::CompareOptions Thresholds::compare_options() const {
  image::CompareOptions o;
  o.pixel_threshold = pixel_threshold;
  o.max_failing_fraction = max_failing_fraction;
  o.compare_alpha = compare_alpha;
  return o;
}

const char* status_name(CaseStatus s) {
  switch (s) {
    case CaseStatus::kPassed:
      return "passed";
    case CaseStatus::kFailed:
      return "failed";
    case CaseStatus::kMissingReference:
      return "missing_reference";
    case CaseStatus::kError:
      return "error";
  }
  return "?";
}

std::size_t Report::count(CaseStatus s) const {
  return static_cast<std::size_t>(
      std::count_if(cases.begin(), cases.end(), [&](const CaseResult& c) { return c.status == s; }));
}

std::string image_file_name(const std::string& asset, const std::string& view) {
  return asset + "__" + view + ".png";
}
std::string diff_file_name(const std::string& asset, const std::string& view) {
  return asset + "__" + view + ".diff.png";
}

CaseResult judge_view(const std::string& asset, const std::string& view, const image::Image* reference,
                      const image::Image& rendered, const Thresholds& thresholds) {
  CaseResult c;
  c.asset = asset;
  c.view = view;
  c.image_file = image_file_name(asset, view);
  c.width = rendered.width();
  c.height = rendered.height();
  if (!reference) {
    c.status = CaseStatus::kMissingReference;
    c.message = "no reference image '" + c.image_file + "' in the references directory";
    return c;
  }
  c.diff_file = diff_file_name(asset, view);
  c.compared = true;
  c.compare = image::compare_images(*reference, rendered, thresholds.compare_options());
  std::string why = c.compare.failure;
  // PSNR is checked only for images that can be compared at all; +inf (identical) always passes.
  if (thresholds.min_psnr_db > 0 && !c.compare.size_mismatch && c.compare.psnr < thresholds.min_psnr_db)
    why += std::string(why.empty() ? "" : "; ") + "PSNR " + fixed(c.compare.psnr, 2) +
           " dB is below the minimum " + fixed(thresholds.min_psnr_db, 2) + " dB";
  c.status = why.empty() ? CaseStatus::kPassed : CaseStatus::kFailed;
  c.message = why;
  return c;
}

namespace {

// A forest's views: its own camera set, each view with its own LOD selection and culling.
std::vector<render::RenderedView> render_forest(const Asset& asset, render::Renderer& renderer) {
  render::ForestView fv = render::ForestView::load(asset.file);
  const render::CameraSet set = render::load_camera_set(asset.file.parent_path() / "cameras.yaml");
  const std::vector<render::Camera> cams = render::forest_cameras(set, fv.bounds());
  std::vector<image::Image> images = fv.render(renderer, cams, render::options_for(set));
  std::vector<render::RenderedView> out;
  for (std::size_t i = 0; i < cams.size(); ++i) out.push_back({cams[i], std::move(images[i])});
  return out;
}

}  // namespace

Report run_verification(const std::vector<Asset>& assets, const render::CameraSet& cameras,
                        const fs::path& references_dir, const Thresholds& thresholds, const RunEnv& env) {
  // 1. Check names: they become file names, and two assets must never share one.
  std::set<std::string> seen;
  for (const Asset& a : assets) {
    if (!valid_name(a.name))
      throw VerifyError("invalid asset name '" + a.name + "' (allowed: letters, digits, '_', '-', '.')");
    if (!seen.insert(a.name).second) throw VerifyError("two assets are named '" + a.name + "'");
  }

  Report report;
  report.device = env.renderer.device_description();
  report.thresholds = thresholds;
  report.width = cameras.width;
  report.height = cameras.height;
  report.msaa = cameras.msaa;
  for (const auto& v : cameras.views) report.views.push_back(v.name);
  for (const auto& a : assets) report.assets.push_back(a.name);

  const fileio::FileSource& files = env.files ? *env.files : fileio::disk_files();
  auto write = [&](const std::string& name, const std::string& bytes) {
    write_bytes(env.output_path(name), bytes);
  };

  for (const Asset& asset : assets) {
    if (env.check_cancelled) env.check_cancelled();
    // 2. Load. A broken asset is one error case per view; the others still get verified.
    render::Scene scene;
    std::vector<render::RenderedView> rendered;
    try {
      if (asset.forest) {
        rendered = render_forest(asset, env.renderer);
        for (const auto& rv : rendered)
          if (std::find(report.views.begin(), report.views.end(), rv.camera.name) == report.views.end())
            report.views.push_back(rv.camera.name);
      } else {
        scene = render::load_gltf_scene(asset.file, files);
      }
    } catch (const render::RenderUnavailableError&) {
      throw;
    } catch (const render::RenderError& e) {
      throw VerifyError(asset.file.string() + ": error: rendering failed: " + e.what());
    } catch (const std::runtime_error& e) {  // SceneLoadError, forest::FormatError, CameraSetError
      for (const auto& v : cameras.views) {
        CaseResult c;
        c.asset = asset.name;
        c.view = v.name;
        c.status = CaseStatus::kError;
        c.message = e.what();
        report.cases.push_back(std::move(c));
      }
      continue;
    }

    // 3. Render every view with one upload.
    try {
      if (!asset.forest) rendered = render::render_camera_set(env.renderer, scene, cameras);
    } catch (const render::RenderUnavailableError&) {
      throw;
    } catch (const render::RenderError& e) {
      throw VerifyError(asset.file.string() + ": error: rendering failed: " + e.what());
    }

    // 4. Per view: write the rendering, read the reference, judge, write the heat map.
    for (const render::RenderedView& rv : rendered) {
      const std::string& view = rv.camera.name;
      const std::string file = image_file_name(asset.name, view);
      std::string png;
      try {
        png = png_bytes(rv.image);
      } catch (const image::ImageError& e) {
        throw VerifyError(e.what());
      }
      write(file, png);

      const fs::path ref_path = references_dir / file;
      std::error_code ec;
      CaseResult c;
      if (!files.exists(ref_path)) {
        c = judge_view(asset.name, view, nullptr, rv.image, thresholds);
      } else {
        image::Image ref;
        std::string ref_png;
        std::optional<std::string> unreadable;
        try {
          ref = image::read_image(ref_path);
          ref_png = files.read(ref_path);
        } catch (const image::ImageError& e) {
          unreadable = e.what();
        } catch (const fileio::FileReadError& e) {
          unreadable = e.what();
        }
        if (unreadable) {
          c = judge_view(asset.name, view, nullptr, rv.image, thresholds);
          c.status = CaseStatus::kError;
          c.message = "the reference image cannot be read: " + *unreadable;
          c.image_png = png;
          report.cases.push_back(std::move(c));
          continue;
        }
        c = judge_view(asset.name, view, &ref, rv.image, thresholds);
        c.reference_png = std::move(ref_png);
        c.diff_png = png_bytes(image::diff_heatmap(ref, rv.image, thresholds.compare_options()));
        write(c.diff_file, c.diff_png);
      }
      c.image_png = std::move(png);
      report.cases.push_back(std::move(c));
    }
  }

  // 5. References that no current view uses (renamed or removed views).
  report.unused_references = unused_references(references_dir, report.assets, report.views);
  return report;
}

}  // namespace sylva::verify
