// The instances.json / instances.bin reader and writer. nlohmann::json keeps object keys sorted
// and prints doubles in shortest round-trip form, so the bytes are deterministic and every double
// reads back bit for bit. The binary table is written field by field in little-endian order
// (not by memcpy of a struct), so its bytes do not depend on padding or on the host.
#include "libs/forest/instances.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

namespace sylva::forest {

namespace {

using nlohmann::json;

constexpr const char* kFormat = "sylva-forest";
constexpr int kVersion = 1;

json vec(const Vec3d& v) { return json::array({v[0], v[1], v[2]}); }
json box_json(const Box3& b) { return {{"min", vec(b.min)}, {"max", vec(b.max)}}; }

json level_json(const Level& l) {
  json j = {{"file", l.file},
            {"epsilon_m", l.epsilon_m},
            {"switch_distance_m", l.switch_distance_m},
            {"primitives", l.primitives},
            {"impostor", l.impostor}};
  if (!l.octahedral.empty()) j["octahedral"] = l.octahedral;
  if (!l.parallax.empty()) {
    json rows = json::array();
    for (const ParallaxStep& p : l.parallax) rows.push_back({{"from_m", p.from_m}, {"steps", p.steps}});
    j["parallax"] = rows;
  }
  return j;
}

json species_json(const Species& s) {
  json levels = json::array();
  for (const Level& l : s.levels) levels.push_back(level_json(l));
  return {{"name", s.name},
          {"source", s.source},
          {"bounds", box_json(s.bounds)},
          {"base_rotation_deg", vec(s.base_rotation_deg)},
          {"base_translation_y_m", s.base_translation_y_m},
          {"camera", {{"fov_y_deg", s.fov_y_deg}, {"height_px", s.height_px}}},
          {"pixel_error_px", s.pixel_error_px},
          {"levels", levels}};
}

json instance_json(const Instance& i) {
  return {{"id", i.id},           {"species", i.species}, {"tile", i.tile}, {"position", vec(i.position)},
          {"yaw_rad", i.yaw_rad}, {"scale", vec(i.scale)}};
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((v >> (8 * b)) & 0xffu));
}
void put_f64(std::string& out, double d) {
  const auto v = std::bit_cast<std::uint64_t>(d);
  for (int b = 0; b < 8; ++b) out.push_back(static_cast<char>((v >> (8 * b)) & 0xffu));
}
std::uint32_t get_u32(const unsigned char* p) {
  std::uint32_t v = 0;
  for (int b = 0; b < 4; ++b) v |= std::uint32_t(p[b]) << (8 * b);
  return v;
}
double get_f64(const unsigned char* p) {
  std::uint64_t v = 0;
  for (int b = 0; b < 8; ++b) v |= std::uint64_t(p[b]) << (8 * b);
  return std::bit_cast<double>(v);
}

// ---- parsing with located errors ----------------------------------------------------------------

class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& what) const { throw FormatError(source_ + ": error: " + what); }

  const json& at(const json& obj, const char* key, const std::string& where) const {
    if (!obj.is_object()) fail(where + " is not an object");
    auto it = obj.find(key);
    if (it == obj.end()) fail(where + " has no '" + key + "'");
    return *it;
  }
  double real(const json& obj, const char* key, const std::string& where, double lo = -INFINITY,
              double hi = INFINITY) const {
    const json& v = at(obj, key, where);
    if (!v.is_number()) fail(where + "." + key + " is not a number");
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) fail(where + "." + key + " is out of range");
    return d;
  }
  std::uint64_t uint(const json& obj, const char* key, const std::string& where, std::uint64_t hi) const {
    const json& v = at(obj, key, where);
    if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<std::int64_t>() >= 0))
      fail(where + "." + key + " is not a non-negative integer");
    const std::uint64_t u = v.get<std::uint64_t>();
    if (u > hi) fail(where + "." + key + " is out of range");
    return u;
  }
  bool boolean(const json& obj, const char* key, const std::string& where) const {
    const json& v = at(obj, key, where);
    if (!v.is_boolean()) fail(where + "." + key + " is not a boolean");
    return v.get<bool>();
  }
  std::string string(const json& obj, const char* key, const std::string& where) const {
    const json& v = at(obj, key, where);
    if (!v.is_string()) fail(where + "." + key + " is not a string");
    return v.get<std::string>();
  }
  const json& array(const json& obj, const char* key, const std::string& where) const {
    const json& v = at(obj, key, where);
    if (!v.is_array()) fail(where + "." + key + " is not an array");
    return v;
  }
  Vec3d vec3(const json& obj, const char* key, const std::string& where) const {
    const json& v = array(obj, key, where);
    if (v.size() != 3) fail(where + "." + key + " does not have 3 numbers");
    Vec3d out{};
    for (std::size_t k = 0; k < 3; ++k) {
      if (!v[k].is_number()) fail(where + "." + key + " does not have 3 numbers");
      out[k] = v[k].get<double>();
      if (!std::isfinite(out[k])) fail(where + "." + key + " is not finite");
    }
    return out;
  }
  Box3 box(const json& obj, const char* key, const std::string& where) const {
    const json& b = at(obj, key, where);
    const std::string w = where + "." + key;
    Box3 out{vec3(b, "min", w), vec3(b, "max", w)};
    for (int k = 0; k < 3; ++k)
      if (out.min[k] > out.max[k]) fail(w + " has min > max");
    return out;
  }

 private:
  std::string source_;
};

// ---- instances.json, section by section ---------------------------------------------------------

// The file's format, version, extent, tiling, method, seed and ground.
void parse_header(const Reader& r, const json& j, Forest& f) {
  if (r.string(j, "format", "the file") != kFormat) r.fail("format is not '" + std::string(kFormat) + "'");
  if (r.uint(j, "version", "the file", 1000) != kVersion) r.fail("unsupported version (this reader knows 1)");
  const json& ext = r.at(j, "extent_m", "the file");
  const json& emin = r.array(ext, "min", "extent_m");
  const json& emax = r.array(ext, "max", "extent_m");
  if (emin.size() != 2 || emax.size() != 2 || !emin[0].is_number() || !emin[1].is_number() ||
      !emax[0].is_number() || !emax[1].is_number())
    r.fail("extent_m.min and .max must be [x, z]");
  f.extent_min = {emin[0].get<double>(), emin[1].get<double>()};
  f.extent_max = {emax[0].get<double>(), emax[1].get<double>()};
  f.tile_size_m = r.real(j, "tile_size_m", "the file", 0);
  f.nodes_per_node = int(r.uint(j, "nodes_per_node", "the file", 1u << 20));
  f.method = r.string(j, "method", "the file");
  f.seed = r.uint(j, "seed", "the file", UINT64_MAX);
  if (j.contains("ground")) {
    f.ground = r.string(j, "ground", "the file");
    if (f.ground.empty() || f.ground.find_first_of("/\\") != std::string::npos || f.ground[0] == '.')
      r.fail("ground must be a file name of this artifact");
  }
}

// One entry of a species' levels; `lw` names it in messages.
Level parse_level(const Reader& r, const json& lj, const std::string& lw) {
  Level lv;
  lv.file = r.string(lj, "file", lw);
  if (lv.file.empty() || lv.file.find_first_of("/\\") != std::string::npos || lv.file[0] == '.')
    r.fail(lw + ".file must be a file name of this artifact");
  lv.epsilon_m = r.real(lj, "epsilon_m", lw, 0);
  // Not necessarily increasing: an impostor proven nearer than the last mesh level's switch
  // distance takes over from there, and that mesh level is never drawn.
  lv.switch_distance_m = r.real(lj, "switch_distance_m", lw, 0);
  lv.primitives = r.uint(lj, "primitives", lw, UINT64_MAX);
  lv.impostor = r.boolean(lj, "impostor", lw);
  if (lj.contains("octahedral")) {
    lv.octahedral = r.string(lj, "octahedral", lw);
    if (!lv.impostor || lv.octahedral.empty() || lv.octahedral.find_first_of("/\\") != std::string::npos ||
        lv.octahedral[0] == '.')
      r.fail(lw + ".octahedral must be a file name of this artifact, on the impostor level only");
  }
  if (lj.contains("parallax")) {
    if (lv.octahedral.empty()) r.fail(lw + ".parallax is for an octahedral impostor level only");
    const json& rows = r.array(lj, "parallax", lw);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const std::string pw = lw + ".parallax[" + std::to_string(k) + "]";
      ParallaxStep p;
      p.from_m = r.real(rows[k], "from_m", pw, 0);
      p.steps = int(r.uint(rows[k], "steps", pw, 64));
      if (!lv.parallax.empty() && !(p.from_m > lv.parallax.back().from_m))
        r.fail(pw + ".from_m must be greater than the row before's");
      lv.parallax.push_back(p);
    }
  }
  return lv;
}

// One entry of species (its stats aside); `w` names it in messages.
Species parse_species(const Reader& r, const json& sj, const std::string& w) {
  Species sp;
  sp.name = r.string(sj, "name", w);
  sp.source = r.string(sj, "source", w);
  sp.bounds = r.box(sj, "bounds", w);
  sp.base_rotation_deg = r.vec3(sj, "base_rotation_deg", w);
  sp.base_translation_y_m = r.real(sj, "base_translation_y_m", w);
  const json& cam = r.at(sj, "camera", w);
  sp.fov_y_deg = r.real(cam, "fov_y_deg", w + ".camera", 1e-6, 179.999);
  sp.height_px = int(r.uint(cam, "height_px", w + ".camera", 1u << 20));
  if (sp.height_px < 1) r.fail(w + ".camera.height_px is out of range");
  sp.pixel_error_px = r.real(sj, "pixel_error_px", w, 1e-9);
  const json& levels = r.array(sj, "levels", w);
  if (levels.empty()) r.fail(w + ".levels is empty");
  for (std::size_t l = 0; l < levels.size(); ++l)
    sp.levels.push_back(parse_level(r, levels[l], w + ".levels[" + std::to_string(l) + "]"));
  return sp;
}

// Every species and its stats.
void parse_species_list(const Reader& r, const json& j, Forest& f) {
  const json& species = r.array(j, "species", "the file");
  for (std::size_t s = 0; s < species.size(); ++s) {
    const std::string w = "species[" + std::to_string(s) + "]";
    const json& sj = species[s];
    Species sp = parse_species(r, sj, w);
    const json& st = r.at(sj, "stats", w);
    f.stats.push_back({r.uint(st, "requested", w + ".stats", UINT64_MAX),
                       r.uint(st, "placed", w + ".stats", UINT64_MAX),
                       r.uint(st, "dropped", w + ".stats", UINT64_MAX)});
    f.species.push_back(std::move(sp));
  }
}

// The instances as a binary table in `bin` (instances is {file, record_bytes}).
void parse_instance_table(const Reader& r, const json& inst, const std::string& bin, std::size_t count,
                          Forest& f) {
  f.binary_table = true;
  if (r.uint(inst, "record_bytes", "instances", 1u << 20) != kRecordBytes)
    r.fail("instances.record_bytes is not " + std::to_string(kRecordBytes));
  if (bin.size() != count * kRecordBytes)
    r.fail(std::string(kInstancesBin) + " holds " + std::to_string(bin.size()) + " bytes, expected " +
           std::to_string(count * kRecordBytes) + " (" + std::to_string(count) + " records)");
  const auto* p = reinterpret_cast<const unsigned char*>(bin.data());
  f.instances.resize(count);
  for (std::size_t i = 0; i < count; ++i, p += kRecordBytes) {
    Instance& in = f.instances[i];
    in.id = get_u32(p);
    in.species = get_u32(p + 4);
    in.tile = get_u32(p + 8);
    for (int k = 0; k < 3; ++k) in.position[std::size_t(k)] = get_f64(p + 12 + 8 * k);
    in.yaw_rad = get_f64(p + 36);
    for (int k = 0; k < 3; ++k) in.scale[std::size_t(k)] = get_f64(p + 44 + 8 * k);
  }
}

// The instances as a JSON array.
void parse_instance_array(const Reader& r, const json& inst, std::size_t count, Forest& f) {
  if (!inst.is_array()) r.fail("instances is neither an array nor a binary table reference");
  if (inst.size() != count)
    r.fail("instances has " + std::to_string(inst.size()) + " entries, instance_count says " +
           std::to_string(count));
  f.instances.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::string w = "instances[" + std::to_string(i) + "]";
    Instance& in = f.instances[i];
    in.id = std::uint32_t(r.uint(inst[i], "id", w, UINT32_MAX));
    in.species = std::uint32_t(r.uint(inst[i], "species", w, UINT32_MAX));
    in.tile = std::uint32_t(r.uint(inst[i], "tile", w, UINT32_MAX));
    in.position = r.vec3(inst[i], "position", w);
    in.yaw_rad = r.real(inst[i], "yaw_rad", w);
    in.scale = r.vec3(inst[i], "scale", w);
  }
}

// The tiles; their instance indices must be below `count`.
void parse_tiles(const Reader& r, const json& j, std::size_t count, Forest& f) {
  const json& tiles = r.array(j, "tiles", "the file");
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const std::string w = "tiles[" + std::to_string(t) + "]";
    Tile tile;
    const json& ix = r.at(tiles[t], "ix", w);
    const json& iz = r.at(tiles[t], "iz", w);
    if (!ix.is_number_integer() || !iz.is_number_integer()) r.fail(w + ".ix/.iz are not integers");
    tile.ix = ix.get<int>();
    tile.iz = iz.get<int>();
    tile.bounds = r.box(tiles[t], "bounds", w);
    for (const json& v : r.array(tiles[t], "instances", w)) {
      if (!v.is_number_unsigned() || v.get<std::uint64_t>() >= count)
        r.fail(w + ".instances has an index out of range");
      tile.instances.push_back(v.get<std::uint32_t>());
    }
    f.tiles.push_back(std::move(tile));
  }
}

// The hierarchy: a leaf's children are instances (below `count`), an inner node's are nodes.
void parse_hierarchy(const Reader& r, const json& j, std::size_t count, Forest& f) {
  const json& nodes = r.array(j, "hierarchy", "the file");
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const std::string w = "hierarchy[" + std::to_string(n) + "]";
    HierarchyNode node;
    node.bounds = r.box(nodes[n], "bounds", w);
    node.leaf = r.boolean(nodes[n], "leaf", w);
    const std::size_t limit = node.leaf ? count : nodes.size();
    for (const json& v : r.array(nodes[n], "children", w)) {
      if (!v.is_number_unsigned() || v.get<std::uint64_t>() >= limit)
        r.fail(w + ".children has an index out of range");
      node.children.push_back(v.get<std::uint32_t>());
    }
    f.hierarchy.push_back(std::move(node));
  }
}

// Every instance: its id is its index, its species and tile exist, its numbers are finite.
void check_instances(const Reader& r, const Forest& f) {
  for (std::size_t i = 0; i < f.instances.size(); ++i) {
    const Instance& in = f.instances[i];
    const std::string w = "instance " + std::to_string(i);
    if (in.id != i) r.fail(w + " has id " + std::to_string(in.id) + " (ids are the instances' indices)");
    if (in.species >= f.species.size())
      r.fail(w + " names species " + std::to_string(in.species) + ", which does not exist");
    if (in.tile >= f.tiles.size())
      r.fail(w + " names tile " + std::to_string(in.tile) + ", which does not exist");
    for (double d : in.position)
      if (!std::isfinite(d)) r.fail(w + " has a non-finite position");
    for (double d : in.scale)
      if (!(d > 0) || !std::isfinite(d)) r.fail(w + " has a scale that is not positive");
    if (!std::isfinite(in.yaw_rad)) r.fail(w + " has a non-finite yaw");
  }
}

}  // namespace

EncodedForest write_instances(const Forest& f) {
  json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["extent_m"] = {{"min", {f.extent_min[0], f.extent_min[1]}}, {"max", {f.extent_max[0], f.extent_max[1]}}};
  j["tile_size_m"] = f.tile_size_m;
  j["nodes_per_node"] = f.nodes_per_node;
  j["method"] = f.method;
  j["seed"] = f.seed;
  if (!f.ground.empty()) j["ground"] = f.ground;
  json species = json::array();
  for (std::size_t s = 0; s < f.species.size(); ++s) {
    json sj = species_json(f.species[s]);
    const SpeciesStats st = s < f.stats.size() ? f.stats[s] : SpeciesStats{};
    sj["stats"] = {{"requested", st.requested}, {"placed", st.placed}, {"dropped", st.dropped}};
    species.push_back(std::move(sj));
  }
  j["species"] = std::move(species);
  json tiles = json::array();
  for (const Tile& t : f.tiles)
    tiles.push_back({{"ix", t.ix}, {"iz", t.iz}, {"bounds", box_json(t.bounds)}, {"instances", t.instances}});
  j["tiles"] = std::move(tiles);
  json nodes = json::array();
  for (const HierarchyNode& n : f.hierarchy)
    nodes.push_back({{"bounds", box_json(n.bounds)}, {"leaf", n.leaf}, {"children", n.children}});
  j["hierarchy"] = std::move(nodes);
  j["instance_count"] = f.instances.size();
  EncodedForest out;
  if (f.binary_table) {
    j["instances"] = {{"file", kInstancesBin}, {"record_bytes", kRecordBytes}};
    out.bin.reserve(f.instances.size() * kRecordBytes);
    for (const Instance& i : f.instances) {
      put_u32(out.bin, i.id);
      put_u32(out.bin, i.species);
      put_u32(out.bin, i.tile);
      for (double d : i.position) put_f64(out.bin, d);
      put_f64(out.bin, i.yaw_rad);
      for (double d : i.scale) put_f64(out.bin, d);
    }
  } else {
    json inst = json::array();
    for (const Instance& i : f.instances) inst.push_back(instance_json(i));
    j["instances"] = std::move(inst);
  }
  out.json = j.dump(1) + "\n";
  return out;
}

Forest parse_instances(const std::string& text, const std::string& bin, const std::string& source_name) {
  const Reader r(source_name);
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {  // a syntax error, or a number beyond a double (1e999)
    r.fail(std::string("not JSON: ") + e.what());
  }
  Forest f;
  parse_header(r, j, f);
  parse_species_list(r, j, f);
  const std::size_t count = r.uint(j, "instance_count", "the file", UINT32_MAX);
  const json& inst = r.at(j, "instances", "the file");
  if (inst.is_object())
    parse_instance_table(r, inst, bin, count, f);
  else
    parse_instance_array(r, inst, count, f);
  parse_tiles(r, j, count, f);
  parse_hierarchy(r, j, count, f);
  check_instances(r, f);
  return f;
}

Forest read_instances(const std::filesystem::path& json_path, const fileio::FileSource& files) {
  auto slurp = [&](const std::filesystem::path& p) {
    try {
      return files.read(p);
    } catch (const fileio::FileReadError& e) {
      throw FormatError(e.what());
    }
  };
  const std::string text = slurp(json_path);
  const std::filesystem::path bin_path = json_path.parent_path() / kInstancesBin;
  const std::string bin = files.exists(bin_path) ? slurp(bin_path) : std::string();
  return parse_instances(text, bin, json_path.string());
}

namespace {

using Mat = std::array<double, 16>;

Mat identity() {
  Mat m{};
  m[0] = m[5] = m[10] = m[15] = 1;
  return m;
}
Mat mul(const Mat& a, const Mat& b) {  // column-major a * b
  Mat c{};
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[std::size_t(k * 4 + row)] * b[std::size_t(col * 4 + k)];
      c[std::size_t(col * 4 + row)] = s;
    }
  return c;
}
Mat rotation(int axis, double rad) {
  Mat m = identity();
  const double c = std::cos(rad), s = std::sin(rad);
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // the rotated plane (a, b), right-handed
  m[std::size_t(a * 4 + a)] = c;
  m[std::size_t(a * 4 + b)] = s;
  m[std::size_t(b * 4 + a)] = -s;
  m[std::size_t(b * 4 + b)] = c;
  return m;
}
Mat translation(const Vec3d& t) {
  Mat m = identity();
  m[12] = t[0];
  m[13] = t[1];
  m[14] = t[2];
  return m;
}
Mat scaling(const Vec3d& s) {
  Mat m = identity();
  m[0] = s[0];
  m[5] = s[1];
  m[10] = s[2];
  return m;
}

}  // namespace

std::array<double, 16> base_matrix(const Species& s) {
  constexpr double kDeg = std::numbers::pi / 180;
  Mat m = rotation(0, s.base_rotation_deg[0] * kDeg);
  m = mul(rotation(1, s.base_rotation_deg[1] * kDeg), m);
  m = mul(rotation(2, s.base_rotation_deg[2] * kDeg), m);
  return mul(translation({0, s.base_translation_y_m, 0}), m);
}

std::array<double, 16> instance_matrix(const Species& species, const Instance& inst) {
  return mul(translation(inst.position),
             mul(rotation(1, inst.yaw_rad), mul(scaling(inst.scale), base_matrix(species))));
}

Box3 transform_box(const std::array<double, 16>& m, const Box3& box) {
  Box3 out{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (int c = 0; c < 8; ++c) {
    const Vec3d p{(c & 1) ? box.max[0] : box.min[0], (c & 2) ? box.max[1] : box.min[1],
                  (c & 4) ? box.max[2] : box.min[2]};
    for (int r = 0; r < 3; ++r) {
      const double v = m[std::size_t(r)] * p[0] + m[std::size_t(4 + r)] * p[1] +
                       m[std::size_t(8 + r)] * p[2] + m[std::size_t(12 + r)];
      out.min[std::size_t(r)] = std::min(out.min[std::size_t(r)], v);
      out.max[std::size_t(r)] = std::max(out.max[std::size_t(r)], v);
    }
  }
  return out;
}

}  // namespace sylva::forest
