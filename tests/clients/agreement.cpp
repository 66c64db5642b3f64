// The second-renderer check (agreement.h): cameras, the image comparison, the three.js batch.
#include "tests/clients/agreement.h"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "libs/fileio/read_file.h"

namespace sylva::clients {

namespace fs = std::filesystem;

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::kMesh:
      return "mesh";
    case Kind::kDracoMesh:
      return "draco mesh";
    case Kind::kLevel:
      return "level";
    case Kind::kLineLevel:
      return "line level";
    case Kind::kRibbons:
      return "ribbons";
    case Kind::kChain:
      return "MSFT_lod chain";
    case Kind::kImpostor:
      return "impostor cards";
    case Kind::kForestTile:
      return "forest tile";
  }
  return "?";
}

// docs/clients.md "The second renderer" derives each number: the silhouette bound is the
// issue's 0.9 for every kind; the colour bound is what the two renderers' known differences
// can produce for that kind, with room for other trees.
Bound bound_for(Kind k) {
  switch (k) {
    case Kind::kLevel:  // opaque lit triangles, no texture: PBR specular vs Lambert only
    case Kind::kRibbons:
      return {0.9, 4.0};
    case Kind::kMesh:  // + textured bark and alpha-masked leaves: mip and filter choices
    case Kind::kDracoMesh:
    case Kind::kLineLevel:   // + blended lines: three.js sorts objects, sylva every element
    case Kind::kChain:       // as its level 0
    case Kind::kImpostor:    // unlit blended cards: three.js sorts objects, sylva every triangle
    case Kind::kForestTile:  // instanced levels: the kinds above, several trees
      return {0.9, 8.0};
  }
  return {};
}

std::vector<render::Camera> views(const render::Bounds& b) {
  const float fov = 40.f;
  const float t = std::tan(fov * 0.5f * 3.14159265f / 180.f);
  const render::Vec3 size = b.max - b.min;
  const render::Vec3 c = b.center();
  std::vector<render::Camera> out;
  // Tree: the front face of the box fills the frame (the larger of its half width and half
  // height at the frame's half height), seen from the front face.
  {
    render::Camera cam;
    cam.name = "tree";
    cam.fov_y_deg = fov;
    const float half = 0.5f * std::max(size.x(), size.y()) * 1.02f;
    const float d = half / t + 0.5f * size.z();
    cam.eye = c + render::Vec3(0, 0, d);
    cam.target = c;
    cam.z_near = std::max(0.01f, d - 0.5f * size.z() - 0.01f * d) * 0.5f;
    cam.z_far = d + size.z();
    out.push_back(cam);
  }
  // Crown: the top third of the box, framed at its front face.
  {
    render::Camera cam;
    cam.name = "crown";
    cam.fov_y_deg = fov;
    const render::Vec3 target(c.x(), b.max.y() - size.y() / 6.f, c.z());
    const float half = size.y() / 6.f;
    const float d = half / t + 0.5f * size.z();
    cam.eye = target + render::Vec3(0, 0, d);
    cam.target = target;
    cam.z_near = std::max(0.01f, (d - 0.5f * size.z()) * 0.5f);
    cam.z_far = d + size.z();
    out.push_back(cam);
  }
  return out;
}

namespace {

// Block averages of an image: per kBlock x kBlock block, the mean coverage (alpha in [0, 1]).
struct Blocks {
  int w = 0, h = 0;
  std::vector<double> cover;  // w*h
};

Blocks blocks(const image::Image& img) {
  Blocks b;
  b.w = img.width() / kBlock;
  b.h = img.height() / kBlock;
  b.cover.assign(std::size_t(b.w) * std::size_t(b.h), 0.0);
  const auto& px = img.bytes();
  const double n = double(kBlock) * kBlock;
  for (int y = 0; y < b.h * kBlock; ++y)
    for (int x = 0; x < b.w * kBlock; ++x) {
      const std::size_t i = (std::size_t(y) * std::size_t(img.width()) + std::size_t(x)) * 4;
      const std::size_t k = std::size_t(y / kBlock) * std::size_t(b.w) + std::size_t(x / kBlock);
      b.cover[k] += px[i + 3] / 255.0 / n;
    }
  return b;
}

}  // namespace

Agreement compare(const image::Image& s, const image::Image& c) {
  if (s.width() != c.width() || s.height() != c.height())
    throw std::invalid_argument("images differ in size: " + std::to_string(s.width()) + "x" +
                                std::to_string(s.height()) + " and " + std::to_string(c.width()) + "x" +
                                std::to_string(c.height()));
  const Blocks a = blocks(s), b = blocks(c);
  double mins = 0, maxs = 0, diff = 0;
  Agreement out;
  for (std::size_t k = 0; k < a.cover.size(); ++k) {
    mins += std::min(a.cover[k], b.cover[k]);
    maxs += std::max(a.cover[k], b.cover[k]);
  }
  // Colour: pixels fully covered in both images (no edge, so no sample-position noise).
  const auto& pa = s.bytes();
  const auto& pb = c.bytes();
  for (std::size_t i = 0; i < pa.size(); i += 4) {
    if (pa[i + 3] == 255 || pb[i + 3] == 255) ++out.either;
    if (pa[i + 3] != 255 || pb[i + 3] != 255) continue;
    ++out.both;
    diff +=
        (std::abs(pa[i] - pb[i]) + std::abs(pa[i + 1] - pb[i + 1]) + std::abs(pa[i + 2] - pb[i + 2])) / 3.0;
  }
  out.iou = maxs > 0 ? mins / maxs : 1.0;
  out.colour = out.both > 0 ? diff / double(out.both) : 0.0;
  return out;
}

render::RenderOptions render_options() {
  render::RenderOptions o;
  o.width = o.height = kViewSize;
  o.msaa = 4;
  o.background = {0, 0, 0, 0};
  return o;
}

namespace {

nlohmann::json vec(const render::Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

ClientResult run_threejs(const std::vector<ClientRender>& renders, const std::vector<LodCheck>& lod_checks,
                         const fs::path& work_dir, const std::vector<LoadCheck>& load_checks) {
  const render::Lighting li;
  nlohmann::json jobs = {{"width", kViewSize},
                         {"height", kViewSize},
                         {"antialias", true},
                         {"lighting",
                          {{"ambient", vec(li.ambient)},
                           {"light_color", vec(li.light_color)},
                           {"direction_to_light", vec(li.direction_to_light.normalized())}}},
                         {"renders", nlohmann::json::array()},
                         {"lod_checks", nlohmann::json::array()},
                         {"load_checks", nlohmann::json::array()}};
  for (const LoadCheck& l : load_checks)
    jobs["load_checks"].push_back({{"file", fs::absolute(l.file).string()}, {"msft_lod", l.msft_lod}});
  for (const ClientRender& r : renders) {
    const render::Camera& c = r.camera;
    jobs["renders"].push_back({{"file", fs::absolute(r.file).string()},
                               {"out", fs::absolute(r.out).string()},
                               {"camera",
                                {{"eye", vec(c.eye)},
                                 {"target", vec(c.target)},
                                 {"up", vec(c.up)},
                                 {"fov_y_deg", c.fov_y_deg},
                                 {"near", c.z_near},
                                 {"far", c.z_far}}}});
  }
  for (const LodCheck& l : lod_checks)
    jobs["lod_checks"].push_back({{"file", fs::absolute(l.file).string()},
                                  {"fov_y_deg", l.fov_y_deg},
                                  {"radius", l.radius},
                                  {"distances", l.distances}});
  fs::create_directories(work_dir);
  const fs::path jobs_file = work_dir / "threejs_jobs.json", result_file = work_dir / "threejs_result.json";
  const fs::path err_file = work_dir / "threejs_stderr.txt";
  std::ofstream(jobs_file) << jobs.dump(2) << "\n";
  fs::remove(result_file);
  const std::string cmd = "node tests/clients/threejs_render.mjs '" + jobs_file.string() + "' '" +
                          result_file.string() + "' 2> '" + err_file.string() + "'";
  const int status = std::system(cmd.c_str());
  ClientResult out;
  out.message = fileio::read_file(err_file);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
  if (code == 3 || code == 127) {
    out.unavailable = true;
    if (out.message.empty()) out.message = "node is not installed";
    return out;
  }
  if (fs::exists(result_file)) out.result = nlohmann::json::parse(fileio::read_file(result_file));
  out.ok = code == 0;
  if (!out.ok && out.message.empty()) out.message = "threejs_render.mjs exited with " + std::to_string(code);
  return out;
}

std::string Row::line() const {
  char buf[512];
  std::snprintf(buf, sizeof buf, "%-9s %-32s %-6s %-15s IoU %.3f %s %.2f   colour %5.2f %s %4.1f   %s",
                client.c_str(), file.c_str(), view.c_str(), kind_name(kind), a.iou,
                a.iou >= bound.min_iou ? ">=" : "< ", bound.min_iou, a.colour,
                a.colour <= bound.max_colour ? "<=" : "> ", bound.max_colour, passed() ? "ok" : "DISAGREE");
  return buf;
}

}  // namespace sylva::clients
