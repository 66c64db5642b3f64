// impostor.json through nlohmann::json: an ordered object so the bytes follow the declaration
// order below, and a reader that checks every field before trusting it (the file may come from
// anywhere, so a bad one is a one-line error, never a crash or a half-filled struct).
#include "libs/impostor/impostor_json.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "libs/fileio/read_file.h"

namespace sylva::impostor {

namespace {

using Json = nlohmann::ordered_json;

constexpr int kFormatVersion = 1;
constexpr const char* kFormatName = "sylva.impostor";

Json vec(const Vec3d& v) { return Json::array({v[0], v[1], v[2]}); }

// The reader: each getter names the path of what it reads in its error.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw ImpostorFormatError(source_ + ": error: " + what);
  }

  const Json& at(const Json& obj, const char* key, const std::string& path) const {
    if (!obj.is_object()) fail("'" + path + "' must be an object");
    auto it = obj.find(key);
    if (it == obj.end()) fail("missing '" + join(path, key) + "'");
    return *it;
  }
  double real(const Json& obj, const char* key, const std::string& path, double lo, double hi) const {
    const Json& v = at(obj, key, path);
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      fail("'" + join(path, key) + "' must be a finite number");
    const double x = v.get<double>();
    if (x < lo || x > hi)
      fail("'" + join(path, key) + "' = " + v.dump() + " is outside [" + num(lo) + ", " + num(hi) + "]");
    return x;
  }
  int integer(const Json& obj, const char* key, const std::string& path, int lo, int hi) const {
    const Json& v = at(obj, key, path);
    if (!v.is_number_integer()) fail("'" + join(path, key) + "' must be an integer");
    const auto x = v.get<long long>();
    if (x < lo || x > hi)
      fail("'" + join(path, key) + "' = " + v.dump() + " is outside [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "]");
    return int(x);
  }
  bool boolean(const Json& obj, const char* key, const std::string& path) const {
    const Json& v = at(obj, key, path);
    if (!v.is_boolean()) fail("'" + join(path, key) + "' must be true or false");
    return v.get<bool>();
  }
  std::string string(const Json& obj, const char* key, const std::string& path) const {
    const Json& v = at(obj, key, path);
    if (!v.is_string()) fail("'" + join(path, key) + "' must be a string");
    return v.get<std::string>();
  }
  Vec3d vec3(const Json& obj, const char* key, const std::string& path) const {
    const Json& v = at(obj, key, path);
    if (!v.is_array() || v.size() != 3) fail("'" + join(path, key) + "' must be a list of three numbers");
    Vec3d out{};
    for (int k = 0; k < 3; ++k) {
      if (!v[k].is_number() || !std::isfinite(v[k].get<double>()))
        fail("'" + join(path, key) + "' must be a list of three finite numbers");
      out[k] = v[k].get<double>();
    }
    return out;
  }

  static std::string join(const std::string& path, const char* key) {
    return path.empty() ? key : path + "." + key;
  }

 private:
  static std::string num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  }
  std::string source_;
};

Kind parse_kind(const Reader& r, const std::string& s) {
  if (s == "hemi_octahedral") return Kind::kHemiOctahedral;
  if (s == "octahedral") return Kind::kOctahedral;
  if (s == "billboards") return Kind::kBillboards;
  r.fail("unknown kind '" + s + "' (expected hemi_octahedral, octahedral or billboards)");
}

double unit_check(const Reader& r, const Vec3d& v, const std::string& what) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (std::abs(n - 1) > 1e-4) r.fail("'" + what + "' must be a unit vector");
  return n;
}

}  // namespace

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::kOctahedral:
      return "octahedral";
    case Kind::kBillboards:
      return "billboards";
    default:
      return "hemi_octahedral";
  }
}

const char* const kFrameDirectionFormula =
    "frame (i, j), column i left to right, row j top to bottom, N = frames_per_side: "
    "p = (2 i / (N - 1) - 1, 2 j / (N - 1) - 1); "
    "hemi: x = (p.x + p.y) / 2, z = (p.x - p.y) / 2, q = (x, 1 - |x| - |z|, z); "
    "full: q = (p.x, 1 - |p.x| - |p.y|, p.y), if q.y < 0 then (q.x, q.z) = ((1 - |p.y|) sgn p.x, (1 - |p.x|) "
    "sgn p.y); "
    "direction (centre toward viewer) = q / |q|; "
    "basis: right = normalize(Y x d) (+X when |d.y| > 1 - 1e-6), up = d x right; "
    "a point X maps to frame uv ((X - c).right / (2 W) + 1/2, 1/2 - (X - c).up / (2 W)); "
    "view v blends the 3 frames of the triangle of grid cell floor(g), g = (encode(v) + 1) / 2 (N - 1), "
    "lower-left triangle when frac(g).x + frac(g).y <= 1, with barycentric weights";

const char* const kDepthEncoding =
    "normal map alpha a = 1/2 + h / (2 R), h = (X - c).d the signed distance of the surface point X from the "
    "plane "
    "through the centre c facing the frame direction d (toward the viewer), R = sphere radius; 1 = nearest "
    "the viewer";

std::string write_impostor_json(const ImpostorInfo& info) {
  Json j;
  j["format"] = kFormatName;
  j["version"] = kFormatVersion;
  j["kind"] = kind_name(info.kind);
  j["hemi"] = info.hemi;
  j["axes"] = {
      {"up", vec({0, 1, 0})}, {"azimuth_zero", vec({0, 0, 1})}, {"handedness", "right"}, {"units", "m"}};
  j["atlas"] = {{"width_px", info.atlas_width_px},
                {"height_px", info.atlas_height_px},
                {"frames_per_side", info.frames_per_side},
                {"frame_px", info.frame_px},
                {"padding_px", info.padding_px},
                {"mip_levels", info.mip_levels},
                {"color", info.color_map},
                {"normal_depth", info.normal_depth_map}};
  j["frame_direction_formula"] = kFrameDirectionFormula;
  j["depth_encoding"] = kDepthEncoding;
  j["bounds"] = {{"min", vec(info.bounds_min)}, {"max", vec(info.bounds_max)}};
  j["sphere"] = {{"center", vec(info.sphere_center)}, {"radius_m", info.sphere_radius}};
  j["frame_half_extent_m"] = info.frame_half_extent;
  j["error"] = {
      {"camera",
       {{"fov_y_deg", lodmodel::degrees(info.camera.fov_y_rad)}, {"height_px", info.camera.height_px}}},
      {"pixel_error_px", info.pixel_error_px},
      {"source_epsilon_m", info.error.source_m},
      {"texel_m", info.error.texel_m},
      {"view_epsilon_m", info.error.view_m},
      {"epsilon_m", info.error.epsilon_m()}};
  j["switch_distance_m"] = info.switch_distance_m;
  j["source"] = {{"type", info.source_type}, {"file", info.source_file}, {"level", info.source_level}};
  Json cards = Json::array();
  for (const Card& c : info.cards) {
    auto polygon = [](const std::vector<Vec2d>& points) {
      Json poly = Json::array();
      for (const Vec2d& p : points) poly.push_back(Json::array({p[0], p[1]}));
      return poly;
    };
    Json card = {{"name", c.name},
                 {"dir", vec(c.dir)},
                 {"right", vec(c.right)},
                 {"up", vec(c.up)},
                 {"center", vec(c.center)},
                 {"half_width_m", c.half_width},
                 {"half_height_m", c.half_height},
                 {"rect_px", Json::array({c.x, c.y, c.w, c.h})},
                 {"cutout_uv", polygon(c.cutout)}};
    if (!c.lower_cutout.empty()) card["lower_cutout_uv"] = polygon(c.lower_cutout);
    cards.push_back(std::move(card));
  }
  j["glb"] = {{"file", info.glb_file}, {"triangles", info.glb_triangles}, {"cards", cards}};
  return j.dump(2) + "\n";
}

namespace {

// "atlas": sizes, which must agree with the frame grid (kinds other than billboards).
void read_atlas(const Reader& r, const Json& j, ImpostorInfo& info) {
  const Json& a = r.at(j, "atlas", "");
  info.atlas_width_px = r.integer(a, "width_px", "atlas", 1, 16384);
  info.atlas_height_px = r.integer(a, "height_px", "atlas", 1, 16384);
  const bool grid = info.kind != Kind::kBillboards;
  info.frames_per_side = r.integer(a, "frames_per_side", "atlas", grid ? 2 : 0, 64);
  info.frame_px = r.integer(a, "frame_px", "atlas", 1, 16384);
  info.padding_px = r.integer(a, "padding_px", "atlas", 0, 8192);
  info.mip_levels = r.integer(a, "mip_levels", "atlas", 0, 14);
  info.color_map = r.string(a, "color", "atlas");
  info.normal_depth_map = r.string(a, "normal_depth", "atlas");
  if (grid && (info.frames_per_side * info.frame_px != info.atlas_width_px ||
               info.frames_per_side * info.frame_px != info.atlas_height_px))
    r.fail("'atlas': width_px and height_px must be frames_per_side * frame_px");
  if (2 * info.padding_px >= info.frame_px) r.fail("'atlas.padding_px' must be less than half of frame_px");
}

// "error": the camera and the error budget the switch distance was chosen with.
void read_error(const Reader& r, const Json& j, ImpostorInfo& info) {
  const Json& e = r.at(j, "error", "");
  const Json& cam = r.at(e, "camera", "error");
  info.camera.fov_y_rad = lodmodel::radians(r.real(cam, "fov_y_deg", "error.camera", 1e-6, 179.999));
  info.camera.height_px = r.integer(cam, "height_px", "error.camera", 1, 1 << 20);
  info.pixel_error_px = r.real(e, "pixel_error_px", "error", 1e-9, 1e9);
  info.error.source_m = r.real(e, "source_epsilon_m", "error", 0, 1e9);
  info.error.texel_m = r.real(e, "texel_m", "error", 0, 1e9);
  info.error.view_m = r.real(e, "view_epsilon_m", "error", 0, 1e9);
}

// A card's cutout polygon `poly` (its `key` at `path`): 3..16 points in [0, 1]^2.
void read_cutout(const Reader& r, const Json& poly, const std::string& path, const std::string& key,
                 std::vector<Vec2d>& out) {
  if (!poly.is_array() || poly.size() < 3 || poly.size() > 16)
    r.fail("'" + path + "." + key + "' must list 3..16 points");
  for (const Json& p : poly) {
    if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
      r.fail("'" + path + "." + key + "' points must be [u, v]");
    const double u = p[0].get<double>(), w = p[1].get<double>();
    if (!(u >= -1e-9 && u <= 1 + 1e-9 && w >= -1e-9 && w <= 1 + 1e-9))
      r.fail("'" + path + "." + key + "' points must lie in [0, 1]^2");
    out.push_back({u, w});
  }
}

// One of "glb.cards" at `path`: a unit-vector frame, a size, a rectangle inside the atlas.
Card read_card(const Reader& r, const Json& cj, const std::string& path, const ImpostorInfo& info) {
  Card c;
  c.name = r.string(cj, "name", path);
  c.dir = r.vec3(cj, "dir", path);
  c.right = r.vec3(cj, "right", path);
  c.up = r.vec3(cj, "up", path);
  unit_check(r, c.dir, path + ".dir");
  unit_check(r, c.right, path + ".right");
  unit_check(r, c.up, path + ".up");
  c.center = r.vec3(cj, "center", path);
  c.half_width = r.real(cj, "half_width_m", path, 1e-9, 1e9);
  c.half_height = r.real(cj, "half_height_m", path, 1e-9, 1e9);
  const Json& rect = r.at(cj, "rect_px", path);
  if (!rect.is_array() || rect.size() != 4) r.fail("'" + path + ".rect_px' must be [x, y, w, h]");
  int v[4];
  for (int q = 0; q < 4; ++q) {
    if (!rect[q].is_number_integer()) r.fail("'" + path + ".rect_px' must be four integers");
    v[q] = rect[q].get<int>();
  }
  c.x = v[0], c.y = v[1], c.w = v[2], c.h = v[3];
  if (c.x < 0 || c.y < 0 || c.w < 1 || c.h < 1 || c.x + c.w > info.atlas_width_px ||
      c.y + c.h > info.atlas_height_px)
    r.fail("'" + path + ".rect_px' lies outside the atlas");
  read_cutout(r, r.at(cj, "cutout_uv", path), path, "cutout_uv", c.cutout);
  if (cj.contains("lower_cutout_uv"))
    read_cutout(r, cj.at("lower_cutout_uv"), path, "lower_cutout_uv", c.lower_cutout);
  return c;
}

// "glb": the file, its triangle count and its cards.
void read_glb(const Reader& r, const Json& j, ImpostorInfo& info) {
  const Json& glb = r.at(j, "glb", "");
  info.glb_file = r.string(glb, "file", "glb");
  const Json& tri = r.at(glb, "triangles", "glb");
  if (!tri.is_number_unsigned()) r.fail("'glb.triangles' must be a non-negative integer");
  info.glb_triangles = tri.get<std::size_t>();
  const Json& cards = r.at(glb, "cards", "glb");
  if (!cards.is_array()) r.fail("'glb.cards' must be a list");
  for (std::size_t k = 0; k < cards.size(); ++k)
    info.cards.push_back(read_card(r, cards[k], "glb.cards[" + std::to_string(k) + "]", info));
}

}  // namespace

ImpostorInfo parse_impostor_json(const std::string& text, const std::string& source_name) {
  const Reader r(source_name);
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {  // a syntax error, or a number beyond a double (1e999)
    r.fail(std::string("invalid JSON: ") + e.what());
  }
  if (!j.is_object()) r.fail("the top level must be an object");
  if (r.string(j, "format", "") != kFormatName)
    r.fail(std::string("'format' must be \"") + kFormatName + "\"");
  const int version = r.integer(j, "version", "", 0, 1 << 20);
  if (version != kFormatVersion)
    r.fail("unsupported version " + std::to_string(version) + " (this reader knows " +
           std::to_string(kFormatVersion) + ")");
  ImpostorInfo info;
  info.kind = parse_kind(r, r.string(j, "kind", ""));
  info.hemi = r.boolean(j, "hemi", "");
  if (info.hemi != (info.kind == Kind::kHemiOctahedral))
    r.fail("'hemi' must be true exactly for kind hemi_octahedral");
  read_atlas(r, j, info);
  const Json& b = r.at(j, "bounds", "");
  info.bounds_min = r.vec3(b, "min", "bounds");
  info.bounds_max = r.vec3(b, "max", "bounds");
  const Json& s = r.at(j, "sphere", "");
  info.sphere_center = r.vec3(s, "center", "sphere");
  info.sphere_radius = r.real(s, "radius_m", "sphere", 1e-9, 1e9);
  info.frame_half_extent = r.real(j, "frame_half_extent_m", "", 1e-9, 1e9);
  read_error(r, j, info);
  info.switch_distance_m = r.real(j, "switch_distance_m", "", 0, 1e12);
  const Json& src = r.at(j, "source", "");
  info.source_type = r.string(src, "type", "source");
  if (info.source_type != "mesh" && info.source_type != "lod")
    r.fail("'source.type' must be \"mesh\" or \"lod\"");
  info.source_file = r.string(src, "file", "source");
  info.source_level = r.integer(src, "level", "source", -1, 64);
  read_glb(r, j, info);
  return info;
}

ImpostorInfo read_impostor_json(const std::string& path) {
  std::string text;
  try {
    text = fileio::read_file(path);
  } catch (const fileio::FileReadError& e) {
    throw ImpostorFormatError(e.what());
  }
  return parse_impostor_json(text, path);
}

}  // namespace sylva::impostor
