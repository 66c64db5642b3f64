// lod.json through nlohmann::json: its (sorted) object gives the bytes the lod stage has always
// written, and a reader that checks every field before trusting it (a lod artifact may come from
// anywhere, so a bad one is a one-line error, never a crash or a half-filled struct).
#include "libs/lodchain/lod_chain.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "libs/fileio/read_file.h"
#include "libs/lodchain/chain_gltf.h"

namespace sylva::lodchain {

namespace {

using Json = nlohmann::json;

constexpr std::size_t kMaxLevels = 8;  // Zhang §6; the lod stage's plan_levels

// The reader: each getter names the path of what it reads in its error.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw LodChainFormatError(source_ + ": error: " + what);
  }

  static std::string join(const std::string& path, const char* key) {
    return path.empty() ? key : path + "." + key;
  }

  // The member `key` of `obj`; `obj` must be an object (the one check of that for every object of
  // the file: the top level, `camera`, `source`, each level, its `counts` and `cards`).
  const Json& at(const Json& obj, const char* key, const std::string& path) const {
    if (!obj.is_object())
      fail(path.empty() ? "the top level must be an object" : "'" + path + "' must be an object");
    auto it = obj.find(key);
    if (it == obj.end()) fail("missing '" + join(path, key) + "'");
    return *it;
  }
  // A finite number x with lo <= x <= hi (lo < x when `open_lo`).
  double real_value(const Json& v, const std::string& name, double lo, double hi, bool open_lo) const {
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail("'" + name + "' must be a finite number");
    const double x = v.get<double>();
    if (open_lo ? !(x > lo) : !(x >= lo)) {
      fail("'" + name + "' = " + v.dump() + (open_lo ? " must be greater than " : " must be at least ") +
           num(lo));
    }
    if (x > hi) fail("'" + name + "' = " + v.dump() + " must be at most " + num(hi));
    return x;
  }
  double real(const Json& obj, const char* key, const std::string& path, double lo, double hi,
              bool open_lo = false) const {
    return real_value(at(obj, key, path), join(path, key), lo, hi, open_lo);
  }
  // null, or a number as real().
  std::optional<double> nullable_real(const Json& obj, const char* key, const std::string& path, double lo,
                                      double hi) const {
    const Json& v = at(obj, key, path);
    if (v.is_null()) return std::nullopt;
    if (!v.is_number()) fail("'" + join(path, key) + "' must be a finite number or null");
    return real_value(v, join(path, key), lo, hi, false);
  }
  std::uint64_t count(const Json& obj, const char* key, const std::string& path) const {
    const Json& v = at(obj, key, path);
    if (!v.is_number_unsigned()) fail("'" + join(path, key) + "' must be a non-negative integer");
    return v.get<std::uint64_t>();
  }
  int integer(const Json& obj, const char* key, const std::string& path, int lo, int hi) const {
    const Json& v = at(obj, key, path);
    if (!v.is_number_integer()) fail("'" + join(path, key) + "' must be an integer");
    const bool too_big = v.is_number_unsigned() && v.get<std::uint64_t>() > std::uint64_t(hi);
    const std::int64_t x = too_big ? hi + std::int64_t(1) : v.get<std::int64_t>();
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
  std::string string(const Json& v, const std::string& name) const {
    if (!v.is_string()) fail("'" + name + "' must be a string");
    return v.get<std::string>();
  }
  std::string string(const Json& obj, const char* key, const std::string& path) const {
    return string(at(obj, key, path), join(path, key));
  }
  std::string file_name(const Json& obj, const char* key, const std::string& path) const {
    std::string s = string(obj, key, path);
    if (s.empty()) fail("'" + join(path, key) + "' must not be empty");
    return s;
  }

 private:
  static std::string num(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  }
  std::string source_;
};

constexpr double kHuge = 1e12;  // no distance, size or budget in a real chain comes near this

// A level: the numbers its glTF extras carry (level_extras), then its files and coverage.
Json level_json(const Level& l) {
  Json j = level_extras(l);
  j["file"] = l.file;
  if (l.ribbons_file) j["ribbons_file"] = *l.ribbons_file;
  j["screen_coverage"] = l.screen_coverage;
  j["coverage_switch_distance_m"] =
      l.coverage_switch_distance_m ? Json(*l.coverage_switch_distance_m) : Json(nullptr);
  if (l.cards) {
    const CardChoice& c = *l.cards;
    j["cards"] = {{"from", c.from},
                  {"cluster_cut", c.cluster_cut},
                  {"clusters_split", c.clusters_split},
                  {"coverage_drift", c.coverage_drift ? Json(*c.coverage_drift) : Json(nullptr)},
                  {"rejected", c.rejected}};
  }
  return j;
}

Level parse_level(const Reader& r, const Json& l, const std::string& path) {
  Level out;
  out.sylva_lod_level = r.count(l, "sylva_lod_level", path);
  out.epsilon_m = r.real(l, "epsilon_m", path, 0, kHuge, true);
  out.pixel_error_px = r.real(l, "pixel_error_px", path, 0, kHuge, true);
  out.switch_distance_m = r.real(l, "switch_distance_m", path, 0, kHuge);
  out.e1_m = r.real(l, "E1_m", path, 0, kHuge);
  out.e2_m = r.real(l, "E2_m", path, 0, kHuge);
  out.e3_m = r.real(l, "E3_m", path, 0, kHuge);
  out.e4_m = r.real(l, "E4_m", path, 0, kHuge);
  out.e5_m = r.real(l, "E5_m", path, 0, kHuge);
  out.line_alpha = r.real(l, "line_alpha", path, 0, 1);
  out.line_alpha_eq12 = r.real(l, "line_alpha_eq12", path, 0, 1);
  out.needle_line_alpha = r.real(l, "needle_line_alpha", path, 0, 1);
  out.needle_line_alpha_eq12 = r.real(l, "needle_line_alpha_eq12", path, 0, 1);
  out.max_polygon_error_m = r.real(l, "max_polygon_error_m", path, 0, kHuge);
  const std::string cp = path + ".counts";
  const Json& c = r.at(l, "counts", path);
  out.counts = {r.count(c, "quads", cp),      r.count(c, "triangles", cp),    r.count(c, "lines", cp),
                r.count(c, "leaves", cp),     r.count(c, "needle_lines", cp), r.count(c, "needle_quads", cp),
                r.count(c, "internodes", cp), r.count(c, "branches", cp)};
  out.file = r.file_name(l, "file", path);
  if (l.contains("ribbons_file")) out.ribbons_file = r.file_name(l, "ribbons_file", path);
  out.screen_coverage = r.real(l, "screen_coverage", path, 0, 1);
  out.coverage_switch_distance_m = r.nullable_real(l, "coverage_switch_distance_m", path, 0, kHuge);
  if (l.contains("cards")) {
    const std::string kp = path + ".cards";
    const Json& k = r.at(l, "cards", path);
    CardChoice cc;
    cc.from = r.string(k, "from", kp);
    if (cc.from != "clusters" && cc.from != "fsa")
      r.fail("'" + kp + ".from' must be \"clusters\" or \"fsa\"");
    cc.cluster_cut = r.count(k, "cluster_cut", kp);
    cc.clusters_split = r.count(k, "clusters_split", kp);
    cc.coverage_drift = r.nullable_real(k, "coverage_drift", kp, -kHuge, kHuge);
    cc.rejected = r.boolean(k, "rejected", kp);
    out.cards = std::move(cc);
  }
  return out;
}

}  // namespace

std::string write_lod_chain(const LodChain& chain) {
  Json j;
  j["tree"] = chain.tree;
  j["camera"] = {{"fov_y_deg", chain.camera_fov_y_deg}, {"height_px", chain.camera_height_px}};
  j["pixel_error_px"] = chain.pixel_error_px;
  j["tree_height_m"] = chain.tree_height_m;
  j["bounding_radius_m"] = chain.bounding_radius_m;
  j["source"] = {{"branches", chain.source.branches},
                 {"leaves", chain.source.leaves},
                 {"needles", chain.source.needles}};
  if (chain.source.model_triangles > 0) j["source"]["model_triangles"] = chain.source.model_triangles;
  j["chain_file"] = chain.chain_file;
  Json levels = Json::array();
  for (const Level& l : chain.levels) levels.push_back(level_json(l));
  j["levels"] = std::move(levels);
  return j.dump(2) + "\n";
}

LodChain parse_lod_chain(const std::string& text, const std::string& source_name) {
  const Reader r(source_name);
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::exception& e) {  // parse_error, and out_of_range for a number like 1e999
    r.fail(std::string("invalid JSON: ") + e.what());
  }
  LodChain c;
  c.tree = r.string(j, "tree", "");
  const Json& cam = r.at(j, "camera", "");
  c.camera_fov_y_deg = r.real(cam, "fov_y_deg", "camera", 0, 180, true);
  if (c.camera_fov_y_deg == 180) r.fail("'camera.fov_y_deg' = 180 must be less than 180");
  c.camera_height_px = r.integer(cam, "height_px", "camera", 1, 1 << 20);
  c.pixel_error_px = r.real(j, "pixel_error_px", "", 0, kHuge, true);
  c.tree_height_m = r.real(j, "tree_height_m", "", 0, kHuge);
  c.bounding_radius_m = r.real(j, "bounding_radius_m", "", 0, kHuge);
  const Json& src = r.at(j, "source", "");
  c.source = {r.count(src, "branches", "source"), r.count(src, "leaves", "source"),
              r.count(src, "needles", "source")};
  if (src.contains("model_triangles")) c.source.model_triangles = r.count(src, "model_triangles", "source");
  c.chain_file = r.file_name(j, "chain_file", "");
  const Json& levels = r.at(j, "levels", "");
  if (!levels.is_array()) r.fail("'levels' must be a list");
  if (levels.empty()) r.fail("'levels' is empty (a chain has at least one level)");
  if (levels.size() > kMaxLevels)
    r.fail("'levels' has " + std::to_string(levels.size()) + " levels, at most " +
           std::to_string(kMaxLevels));
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const std::string path = "levels[" + std::to_string(i) + "]";
    Level l = parse_level(r, levels[i], path);
    if (l.sylva_lod_level != i)
      r.fail("'" + path + ".sylva_lod_level' = " + std::to_string(l.sylva_lod_level) + " must be its index " +
             std::to_string(i));
    if (i > 0 && !(l.epsilon_m > c.levels.back().epsilon_m))
      r.fail("'" + path + ".epsilon_m' = " + Json(l.epsilon_m).dump() +
             " must be greater than the previous level's " + Json(c.levels.back().epsilon_m).dump());
    c.levels.push_back(std::move(l));
  }
  return c;
}

std::string level_name(std::size_t i) { return "lod" + std::to_string(i); }
std::string level_file(std::size_t i) { return level_name(i) + ".gltf"; }
std::string level_bin(std::size_t i) { return level_name(i) + ".bin"; }
std::string ribbons_file(std::size_t i) { return level_name(i) + "_ribbons.gltf"; }
std::string ribbons_bin(std::size_t i) { return level_name(i) + "_ribbons.bin"; }

lodmodel::Camera LodChain::camera() const {
  return lodmodel::camera_from_degrees(camera_fov_y_deg, camera_height_px);
}

LodChain read_lod_chain(const std::string& path) {
  std::string text;
  try {
    text = fileio::read_file(path);
  } catch (const fileio::FileReadError& e) {
    throw LodChainFormatError(e.what());
  }
  return parse_lod_chain(text, path);
}

}  // namespace sylva::lodchain
