// pack/manifest.json through nlohmann::json (its objects keep keys sorted, so dump() is
// canonical); SHA-256 from pipeline/digest.h (OpenSSL).
#include "libs/pack/manifest.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "libs/fileio/read_file.h"
#include "libs/pack/level_json.h"
#include "pipeline/digest.h"

namespace sylva::pack {

namespace {

using nlohmann::json;

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

// A relative path of plain names: no empty, "." or ".." segment, no backslash, not absolute.
bool plain_relative_path(std::string_view p) {
  if (p.empty() || p.front() == '/' || p.find('\\') != std::string_view::npos) return false;
  std::size_t start = 0;
  while (start <= p.size()) {
    const std::size_t end = std::min(p.find('/', start), p.size());
    const std::string_view seg = p.substr(start, end - start);
    if (seg.empty() || seg == "." || seg == "..") return false;
    start = end + 1;
  }
  return true;
}

// Reading with the element's JSON path in every message.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw ManifestError(source_ + ": " + where + ": " + what);
  }
  const json& member(const json& obj, const std::string& where, const char* key) const {
    if (!obj.is_object()) fail(where, "expected an object");
    const auto it = obj.find(key);
    if (it == obj.end()) fail(where, std::string("missing \"") + key + "\"");
    return *it;
  }
  std::string string(const json& obj, const std::string& where, const char* key) const {
    const json& v = member(obj, where, key);
    if (!v.is_string()) fail(where + "." + key, "expected a string");
    return v.get<std::string>();
  }
  std::uint64_t unsigned_integer(const json& obj, const std::string& where, const char* key) const {
    const json& v = member(obj, where, key);
    if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<std::int64_t>() >= 0))
      fail(where + "." + key, "expected a non-negative integer");
    return v.get<std::uint64_t>();
  }
  const json& array(const json& obj, const std::string& where, const char* key) const {
    const json& v = member(obj, where, key);
    if (!v.is_array()) fail(where + "." + key, "expected an array");
    return v;
  }
  std::string digest(const json& obj, const std::string& where, const char* key) const {
    std::string d = string(obj, where, key);
    if (!is_hex_digest(d)) fail(where + "." + key, "expected 64 lowercase hex digits");
    return d;
  }
  double number(const json& obj, const std::string& where, const char* key) const {
    const json& v = member(obj, where, key);
    if (!v.is_number()) fail(where + "." + key, "expected a number");
    return v.get<double>();
  }
  int integer(const json& obj, const std::string& where, const char* key) const {
    const json& v = member(obj, where, key);
    if (!v.is_number_integer() || v.get<std::int64_t>() < -1 || v.get<std::int64_t>() > 1'000'000)
      fail(where + "." + key, "expected an integer from -1 to 1000000");
    return v.get<int>();
  }
  bool boolean(const json& obj, const std::string& where, const char* key) const {
    const json& v = member(obj, where, key);
    if (!v.is_boolean()) fail(where + "." + key, "expected true or false");
    return v.get<bool>();
  }
  // A level object (level_json.h).
  LodLevel level(const json& obj, const std::string& where) const {
    LodLevel l;
    l.file = path(obj, where, "file");
    l.kind = string(obj, where, "kind");
    if (l.kind != "mesh" && l.kind != "impostor") fail(where + ".kind", "expected \"mesh\" or \"impostor\"");
    if (obj.contains("impostor_kind")) l.impostor_kind = string(obj, where, "impostor_kind");
    l.source_level = integer(obj, where, "source_level");
    l.epsilon_m = number(obj, where, "epsilon_m");
    l.pixel_error_px = number(obj, where, "pixel_error_px");
    l.switch_distance_m = number(obj, where, "switch_distance_m");
    l.screen_coverage = number(obj, where, "screen_coverage");
    l.primitives = unsigned_integer(obj, where, "primitives");
    l.triangles = unsigned_integer(obj, where, "triangles");
    l.lines = unsigned_integer(obj, where, "lines");
    l.bytes = unsigned_integer(obj, where, "bytes");
    l.position_bits = integer(obj, where, "position_bits");
    l.position_error_m = number(obj, where, "position_error_m");
    l.position_float = boolean(obj, where, "position_float");
    if (obj.contains("measured")) {
      const std::string at = where + ".measured";
      const json& m = obj["measured"];
      if (!m.is_object()) fail(at, "expected an object");
      l.measured = MeasuredError{number(m, at, "failing_fraction"), number(m, at, "coverage_mean_error"),
                                 boolean(m, at, "passed")};
    }
    return l;
  }
  std::string path(const json& obj, const std::string& where, const char* key) const {
    std::string p = string(obj, where, key);
    if (!plain_relative_path(p))
      fail(where + "." + key, "'" + p.substr(0, 80) + "' is not a plain relative path");
    return p;
  }

 private:
  std::string source_;
};

// Pointers to `items` in the order of the string `key(item)`: the manifest's lists are sorted.
template <class T, class Key>
std::vector<const T*> sorted_by(const std::vector<T>& items, Key key) {
  std::vector<const T*> out;
  for (const auto& item : items) out.push_back(&item);
  std::sort(out.begin(), out.end(), [&](const T* a, const T* b) { return key(*a) < key(*b); });
  return out;
}

}  // namespace

std::uint64_t Manifest::total_bytes() const {
  std::uint64_t sum = 0;
  for (const auto& f : files) sum += f.size;
  return sum;
}

const FileEntry* Manifest::file(std::string_view path) const {
  for (const auto& f : files)
    if (f.path == path) return &f;
  return nullptr;
}

std::string media_type_for(std::string_view path) {
  if (ends_with(path, ".glb")) return "model/gltf-binary";
  if (ends_with(path, ".gltf")) return "model/gltf+json";
  if (ends_with(path, ".json")) return "application/json";
  if (ends_with(path, ".png")) return "image/png";
  if (ends_with(path, ".jpg")) return "image/jpeg";
  if (ends_with(path, ".ktx2")) return "image/ktx2";
  if (ends_with(path, ".yaml")) return "application/yaml";
  return "application/octet-stream";
}

FileEntry describe_file(std::string path, std::string_view bytes, Producer producer) {
  FileEntry e;
  e.media_type = media_type_for(path);
  e.path = std::move(path);
  e.sha256 = sha256_hex(bytes);
  e.size = bytes.size();
  e.producer = std::move(producer);
  return e;
}

std::string write_manifest(const Manifest& manifest) {
  const std::vector<const FileEntry*> files =
      sorted_by(manifest.files, [](const FileEntry& f) -> const std::string& { return f.path; });
  for (std::size_t i = 1; i < files.size(); ++i)
    if (files[i]->path == files[i - 1]->path)
      throw ManifestError("manifest: two files named '" + files[i]->path + "'");
  std::set<std::string> listed;
  // Every path a species or forest names must be one of the pack's files; `owner` names who names it.
  auto require_listed = [&](const std::string& owner, const std::string& p) {
    if (!listed.count(p))
      throw ManifestError("manifest: " + owner + " names '" + p + "', which is not in the pack");
  };
  json jf = json::array();
  for (const FileEntry* f : files) {
    listed.insert(f->path);
    json inputs = json::object();
    for (const auto& [name, digest] : f->producer.inputs) inputs[name] = digest;
    jf.push_back({{"path", f->path},
                  {"sha256", f->sha256},
                  {"size", f->size},
                  {"media_type", f->media_type},
                  {"producer",
                   {{"stage", f->producer.stage},
                    {"stage_version", f->producer.stage_version},
                    {"inputs", std::move(inputs)}}}});
  }
  json js = json::array();
  for (const SpeciesEntry* s :
       sorted_by(manifest.species, [](const SpeciesEntry& e) -> const std::string& { return e.name; })) {
    auto check = [&](const std::string& p) { require_listed("species '" + s->name + "'", p); };
    check(s->chain);
    check(s->lod_json);
    json levels = json::array();
    for (const LodLevel& l : s->levels) {
      check(l.file);
      levels.push_back(level_json(l));
    }
    json e = {
        {"name", s->name}, {"chain", s->chain}, {"lod_json", s->lod_json}, {"levels", std::move(levels)}};
    if (!s->impostor.empty()) {
      check(s->impostor);
      e["impostor"] = s->impostor;
    }
    js.push_back(std::move(e));
  }
  json jforests = json::array();
  for (const ForestEntry* f :
       sorted_by(manifest.forests, [](const ForestEntry& e) -> const std::string& { return e.name; })) {
    auto check = [&](const std::string& p) { require_listed("forest '" + f->name + "'", p); };
    check(f->tileset);
    check(f->instances);
    std::vector<std::string> tiles = f->tiles, all = f->files;
    std::sort(tiles.begin(), tiles.end());
    std::sort(all.begin(), all.end());
    for (const auto& p : tiles) check(p);
    for (const auto& p : all) check(p);
    jforests.push_back({{"name", f->name},
                        {"tileset", f->tileset},
                        {"instances", f->instances},
                        {"tiles", tiles},
                        {"files", all}});
  }
  const json j = {{"format", "sylva-pack-manifest"}, {"version", kManifestVersion},
                  {"files", std::move(jf)},          {"species", std::move(js)},
                  {"forests", std::move(jforests)},  {"total_bytes", manifest.total_bytes()}};
  return j.dump(2) + "\n";
}

namespace {

// `text` as JSON; a syntax error is named by its line:column in `source`.
json parse_json(std::string_view text, const std::string& source) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // e.byte is the offset of the error; name it as line:column.
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    throw ManifestError(source + ":" + std::to_string(line) + ":" + std::to_string(col) + ": not valid JSON");
  } catch (const json::exception&) {  // a number beyond a double (1e999)
    throw ManifestError(source + ": not valid JSON (a number out of range)");
  }
}

// A path a species or forest names, at JSON path `at`, must be one of the files (`paths`).
std::string listed(const Reader& r, const std::set<std::string>& paths, const std::string& p,
                   const std::string& at) {
  if (!paths.count(p)) r.fail(at, "'" + p + "' is not in files");
  return p;
}

// "files": into m.files; returns their paths (each listed once).
std::set<std::string> read_files(const Reader& r, const json& j, Manifest& m) {
  std::set<std::string> paths;
  const json& files = r.array(j, "(root)", "files");
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string where = "files[" + std::to_string(i) + "]";
    const json& f = files[i];
    FileEntry e;
    e.path = r.path(f, where, "path");
    if (!paths.insert(e.path).second) r.fail(where + ".path", "'" + e.path + "' is listed twice");
    e.sha256 = r.digest(f, where, "sha256");
    e.size = r.unsigned_integer(f, where, "size");
    e.media_type = r.string(f, where, "media_type");
    const json& p = r.member(f, where, "producer");
    e.producer.stage = r.string(p, where + ".producer", "stage");
    e.producer.stage_version = static_cast<int>(r.unsigned_integer(p, where + ".producer", "stage_version"));
    const json& in = r.member(p, where + ".producer", "inputs");
    if (!in.is_object()) r.fail(where + ".producer.inputs", "expected an object");
    for (auto it = in.begin(); it != in.end(); ++it) {
      if (!it.value().is_string() || !is_hex_digest(it.value().get<std::string>()))
        r.fail(where + ".producer.inputs." + it.key(), "expected 64 lowercase hex digits");
      e.producer.inputs.emplace(it.key(), it.value().get<std::string>());
    }
    m.files.push_back(std::move(e));
  }
  return paths;
}

// One of a species' "levels" at `at`: a file name before version 3, then an object whose bytes
// must be the file's size.
LodLevel read_level(const Reader& r, const json& level, const std::string& at, std::uint64_t version,
                    const Manifest& m, const std::set<std::string>& paths) {
  LodLevel l;
  if (version < 3) {
    if (!level.is_string()) r.fail(at, "expected a string");
    l.file = listed(r, paths, level.get<std::string>(), at);
  } else {
    l = r.level(level, at);
    listed(r, paths, l.file, at + ".file");
    if (l.bytes != m.file(l.file)->size)
      r.fail(at + ".bytes", std::to_string(l.bytes) + " is not the size of '" + l.file + "' (" +
                                std::to_string(m.file(l.file)->size) + ")");
  }
  return l;
}

void read_species(const Reader& r, const json& j, std::uint64_t version, const std::set<std::string>& paths,
                  Manifest& m) {
  const json& species = r.array(j, "(root)", "species");
  for (std::size_t i = 0; i < species.size(); ++i) {
    const std::string where = "species[" + std::to_string(i) + "]";
    const json& s = species[i];
    SpeciesEntry e;
    e.name = r.string(s, where, "name");
    e.chain = listed(r, paths, r.path(s, where, "chain"), where + ".chain");
    e.lod_json = listed(r, paths, r.path(s, where, "lod_json"), where + ".lod_json");
    const json& levels = r.array(s, where, "levels");
    for (std::size_t k = 0; k < levels.size(); ++k)
      e.levels.push_back(
          read_level(r, levels[k], where + ".levels[" + std::to_string(k) + "]", version, m, paths));
    if (s.is_object() && s.contains("impostor"))
      e.impostor = listed(r, paths, r.path(s, where, "impostor"), where + ".impostor");
    m.species.push_back(std::move(e));
  }
}

void read_forests(const Reader& r, const json& j, const std::set<std::string>& paths, Manifest& m) {
  const json& forests = r.array(j, "(root)", "forests");
  for (std::size_t i = 0; i < forests.size(); ++i) {
    const std::string where = "forests[" + std::to_string(i) + "]";
    const json& f = forests[i];
    ForestEntry e;
    e.name = r.string(f, where, "name");
    e.tileset = listed(r, paths, r.path(f, where, "tileset"), where + ".tileset");
    e.instances = listed(r, paths, r.path(f, where, "instances"), where + ".instances");
    for (const char* key : {"tiles", "files"}) {
      const json& list = r.array(f, where, key);
      std::vector<std::string>& into = std::string(key) == "tiles" ? e.tiles : e.files;
      for (std::size_t k = 0; k < list.size(); ++k) {
        const std::string at = where + "." + key + "[" + std::to_string(k) + "]";
        if (!list[k].is_string()) r.fail(at, "expected a string");
        into.push_back(listed(r, paths, list[k].get<std::string>(), at));
      }
    }
    m.forests.push_back(std::move(e));
  }
}

}  // namespace

Manifest parse_manifest(std::string_view text, const std::string& source) {
  const Reader r(source);
  const json j = parse_json(text, source);
  if (!j.is_object()) r.fail("(root)", "expected an object");
  if (r.string(j, "(root)", "format") != "sylva-pack-manifest")
    r.fail("format", "expected \"sylva-pack-manifest\"");
  const std::uint64_t version = r.unsigned_integer(j, "(root)", "version");
  if (version < 1 || version > std::uint64_t(kManifestVersion))
    r.fail("version", std::to_string(version) + " is not supported (this sylva reads versions 1 to " +
                          std::to_string(kManifestVersion) + ")");
  Manifest m;
  m.version = static_cast<int>(version);
  const std::set<std::string> paths = read_files(r, j, m);
  read_species(r, j, version, paths, m);
  if (version >= 2) read_forests(r, j, paths, m);
  const std::uint64_t total = r.unsigned_integer(j, "(root)", "total_bytes");
  if (total != m.total_bytes())
    r.fail("total_bytes", std::to_string(total) + " is not the sum of the files' sizes (" +
                              std::to_string(m.total_bytes()) + ")");
  return m;
}

Manifest read_manifest(const std::filesystem::path& path) {
  std::string text;
  try {
    text = fileio::read_file(path);
  } catch (const fileio::FileReadError& e) {
    throw ManifestError(e.what());
  }
  return parse_manifest(text, path.string());
}

ManifestDiff diff_manifests(const Manifest& old_manifest, const Manifest& new_manifest) {
  std::map<std::string, std::string> before, after;
  for (const auto& f : old_manifest.files) before.emplace(f.path, f.sha256);
  for (const auto& f : new_manifest.files) after.emplace(f.path, f.sha256);
  ManifestDiff d;
  for (const auto& [path, digest] : after) {
    const auto it = before.find(path);
    if (it == before.end())
      d.added.push_back(path);
    else if (it->second != digest)
      d.changed.push_back(path);
  }
  for (const auto& [path, digest] : before)
    if (!after.count(path)) d.removed.push_back(path);
  return d;
}

}  // namespace sylva::pack
