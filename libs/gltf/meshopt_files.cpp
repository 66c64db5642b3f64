// meshopt_files.h: the forest's shared-buffer glTF files compressed at the JSON level (their
// accessors, materials and instancing stay as written; only views and buffers change), with the
// same view classification and codecs as the GLB writer (meshopt_encode.cpp).
#include "libs/gltf/meshopt_files.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "libs/gltf/meshopt_encode.h"
#include "libs/gltf/writer.h"

namespace sylva::gltf {

namespace {

using nlohmann::json;
constexpr const char* kMeshopt = "EXT_meshopt_compression";

struct Use {
  std::optional<detail::MeshoptMode> mode;  // empty: raw
  std::size_t count = 0, stride = 0;
  friend bool operator==(const Use&, const Use&) = default;
};

using Range = std::pair<std::size_t, std::size_t>;  // byteOffset, byteLength in the .bin

std::size_t component_size(int type) {
  switch (type) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    case 5125:
    case 5126:
      return 4;
    default:
      return 0;
  }
}

std::size_t components(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4" || type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

std::size_t uint_of(const json& obj, const char* key, std::size_t fallback = 0) {
  const auto it = obj.find(key);
  return it != obj.end() && it->is_number_unsigned() ? it->get<std::size_t>() : fallback;
}

const json kEmpty = json::array();

// obj[key] when it is there, else `empty` (a reference: no temporary to iterate over).
const json& member(const json& obj, const char* key, const json& empty) {
  const auto it = obj.find(key);
  return it != obj.end() ? *it : empty;
}

// How each view of a file is used (meshopt_encode.cpp classify(), over JSON).
std::vector<Use> classify(const json& g) {
  const json& views = member(g, "bufferViews", kEmpty);
  const json& accessors = member(g, "accessors", kEmpty);
  std::vector<Use> uses(views.size());
  std::vector<int> refs(views.size(), 0);
  for (const json& a : accessors)
    if (a.contains("bufferView") && uint_of(a, "bufferView") < views.size()) ++refs[uint_of(a, "bufferView")];
  for (const json& im : member(g, "images", kEmpty))
    if (im.contains("bufferView") && uint_of(im, "bufferView") < views.size())
      refs[uint_of(im, "bufferView")] += 2;
  auto mark = [&](const json& index, detail::MeshoptMode mode) {
    if (!index.is_number_unsigned() || index.get<std::size_t>() >= accessors.size()) return;
    const json& a = accessors[index.get<std::size_t>()];
    if (!a.contains("bufferView") || a.contains("sparse") || uint_of(a, "byteOffset") != 0) return;
    const std::size_t v = uint_of(a, "bufferView", views.size());
    if (v >= views.size() || refs[v] != 1) return;
    const json& view = views[v];
    const std::size_t element = component_size(a.value("componentType", 0)) * components(a.value("type", ""));
    const std::size_t stride = uint_of(view, "byteStride");
    const std::size_t size = stride != 0 ? stride : element;
    const std::size_t count = uint_of(a, "count");
    if (element == 0 || (stride != 0 && stride < element)) return;
    if (count == 0 || count * size != uint_of(view, "byteLength")) return;
    if (mode == detail::MeshoptMode::kAttributes && (size % 4 != 0 || size > 252)) return;
    if (mode != detail::MeshoptMode::kAttributes && size != 2 && size != 4) return;
    if (mode == detail::MeshoptMode::kTriangles && count % 3 != 0) mode = detail::MeshoptMode::kIndices;
    uses[v] = {mode, count, size};
  };
  for (const json& mesh : member(g, "meshes", kEmpty))
    for (const json& p : member(mesh, "primitives", kEmpty)) {
      static const json kNoAttributes = json::object();
      for (const auto& [name, acc] : member(p, "attributes", kNoAttributes).items())
        mark(acc, detail::MeshoptMode::kAttributes);
      if (p.contains("indices"))
        mark(p["indices"],
             p.value("mode", 4) == 4 ? detail::MeshoptMode::kTriangles : detail::MeshoptMode::kIndices);
    }
  for (const json& n : member(g, "nodes", kEmpty)) {
    const json* inst = n.contains("extensions") && n["extensions"].contains("EXT_mesh_gpu_instancing")
                           ? &n["extensions"]["EXT_mesh_gpu_instancing"]
                           : nullptr;
    if (inst && inst->contains("attributes") && (*inst)["attributes"].is_object())
      for (const auto& [name, acc] : (*inst)["attributes"].items())
        mark(acc, detail::MeshoptMode::kAttributes);
  }
  return uses;
}

bool uses_extension(const json& g, const char* name) {
  for (const char* list : {"extensionsUsed", "extensionsRequired"})
    for (const json& e : member(g, list, kEmpty))
      if (e.is_string() && e.get<std::string>() == name) return true;
  return false;
}

const char* mode_name(detail::MeshoptMode m) {
  return m == detail::MeshoptMode::kAttributes  ? "ATTRIBUTES"
         : m == detail::MeshoptMode::kTriangles ? "TRIANGLES"
                                                : "INDICES";
}

// A range of a .bin as placed in the new .bin.
struct Placement {
  Use use;  // raw when two files view it differently, or it overlaps another
  bool conflict = false;
  std::size_t offset = 0, length = 0;  // in the new .bin
};

// Every .bin range some view covers, and how it is placed; by .bin uri.
using Ranges = std::map<std::string, std::map<Range, Placement>>;

std::map<std::string, json> parse_files(const GltfFileSet& in) {
  std::map<std::string, json> parsed;
  for (const auto& [name, text] : in.gltf) {
    try {
      parsed.emplace(name, json::parse(text));
    } catch (const json::exception& e) {  // a syntax error, or a number beyond a double (1e999)
      throw GltfError(name + ": not valid JSON (" + e.what() + ")");
    }
    if (!parsed[name].is_object()) throw GltfError(name + ": not a glTF object");
  }
  return parsed;
}

// Files left as they are (already compressed, or with a buffer that is embedded, unnamed or
// pinned), and the .bin files they pin, to a fixed point: a file naming a pinned .bin is left as
// it is too.
std::set<std::string> kept_files(const std::map<std::string, json>& parsed) {
  std::set<std::string> kept, pinned;
  for (bool grew = true; grew;) {
    grew = false;
    for (const auto& [name, g] : parsed) {
      if (kept.count(name)) continue;
      bool keep = uses_extension(g, kMeshopt) || uses_extension(g, "KHR_draco_mesh_compression");
      for (const json& b : member(g, "buffers", kEmpty)) {
        const std::string uri = b.value("uri", "");
        if (uri.empty() || uri.rfind("data:", 0) == 0 || pinned.count(uri)) keep = true;
      }
      if (!keep) continue;
      kept.insert(name);
      for (const json& b : member(g, "buffers", kEmpty))
        if (b.contains("uri")) grew = pinned.insert(b.value("uri", "")).second || grew;
      grew = true;
    }
  }
  return kept;
}

// Every range each .bin is viewed by, and how; a range two files use differently is a conflict.
Ranges view_ranges(const GltfFileSet& in, const std::map<std::string, json>& parsed,
                   const std::set<std::string>& kept) {
  Ranges ranges;
  std::map<std::string, std::vector<Use>> uses;
  for (const auto& [name, g] : parsed) {
    if (kept.count(name)) continue;
    const json& buffers = member(g, "buffers", kEmpty);
    uses[name] = classify(g);
    const json& views = member(g, "bufferViews", kEmpty);
    for (std::size_t v = 0; v < views.size(); ++v) {
      const std::size_t b = uint_of(views[v], "buffer", buffers.size());
      if (b >= buffers.size())
        throw GltfError(name + ": bufferViews[" + std::to_string(v) + "] names no buffer");
      const std::string uri = buffers[b].value("uri", "");
      const auto bin = in.bins.find(uri);
      if (bin == in.bins.end()) throw GltfError(name + ": buffer '" + uri + "' is not among the files");
      const Range r{uint_of(views[v], "byteOffset"), uint_of(views[v], "byteLength")};
      if (r.first + r.second > bin->second.size())
        throw GltfError(name + ": bufferViews[" + std::to_string(v) + "] lies outside '" + uri + "'");
      const auto [it, fresh] = ranges[uri].try_emplace(r, Placement{uses[name][v]});
      if (!fresh && !(it->second.use == uses[name][v])) it->second.conflict = true;
    }
  }
  return ranges;
}

// The new .bin for `src`: its ranges in offset order, compressed or raw, 4-byte aligned; each
// range's placement is filled in (overlapping ranges are conflicts and stay raw).
std::string pack_bin(const std::string& src, std::map<Range, Placement>& placed, MeshoptFilesStats& st) {
  std::string bin;
  std::size_t end = 0;  // the furthest byte a range before this one reaches
  for (auto it = placed.begin(); it != placed.end(); ++it) {
    Placement& p = it->second;
    const Range& r = it->first;
    const auto next = std::next(it);
    if (r.first < end || (next != placed.end() && next->first.first < r.first + r.second)) p.conflict = true;
    end = std::max(end, r.first + r.second);
    if (p.conflict) p.use = Use{};
    while (bin.size() % 4 != 0) bin.push_back('\0');
    p.offset = bin.size();
    const auto* data = reinterpret_cast<const unsigned char*>(src.data()) + r.first;
    // A view the codec would not shrink (a tile's few instances: the codec's block headers
    // outweigh them) is stored raw.
    std::string encoded;
    if (p.use.mode) encoded = detail::encode_meshopt_view(data, *p.use.mode, p.use.count, p.use.stride);
    if (p.use.mode && encoded.size() >= r.second) p.use = Use{};
    if (p.use.mode) {
      bin += encoded;
      ++st.views_compressed;
    } else {
      bin.append(src, r.first, r.second);
      ++st.views_raw;
    }
    p.length = bin.size() - p.offset;
  }
  while (bin.size() % 4 != 0) bin.push_back('\0');
  return bin;
}

// File `g`'s views and buffers pointed at the new .bin files (`new_bins`): a compressed view
// reads its range through EXT_meshopt_compression, with a fallback buffer of the old size.
// Returns the file's new text.
std::string repoint(json& g, const GltfFileSet& in, const Ranges& ranges,
                    const std::map<std::string, std::string>& new_bins) {
  json& buffers = g["buffers"];
  const std::size_t original_buffers = buffers.size();
  std::map<std::size_t, std::size_t> fallback;  // buffer -> its fallback buffer
  json& views = g["bufferViews"];
  bool any = false;
  for (std::size_t v = 0; v < views.size(); ++v) {
    json& view = views[v];
    const std::size_t b = uint_of(view, "buffer");
    const std::string uri = buffers[b].value("uri", "");
    const Placement& p = ranges.at(uri).at(Range{uint_of(view, "byteOffset"), uint_of(view, "byteLength")});
    if (!p.use.mode) {
      view["byteOffset"] = p.offset;
      continue;
    }
    auto [fb, fresh] = fallback.try_emplace(b, buffers.size());
    if (fresh)
      buffers.push_back(
          {{"byteLength", in.bins.at(uri).size()}, {"extensions", {{kMeshopt, {{"fallback", true}}}}}});
    view["buffer"] = fb->second;
    if (*p.use.mode == detail::MeshoptMode::kAttributes) view["byteStride"] = p.use.stride;
    view["extensions"][kMeshopt] = {{"buffer", b},
                                    {"byteOffset", p.offset},
                                    {"byteLength", p.length},
                                    {"byteStride", p.use.stride},
                                    {"count", p.use.count},
                                    {"mode", mode_name(*p.use.mode)}};
    any = true;
  }
  for (std::size_t b = 0; b < original_buffers; ++b)
    buffers[b]["byteLength"] = new_bins.at(buffers[b].value("uri", "")).size();
  if (any)
    for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
      std::vector<std::string> names = g.value(list, std::vector<std::string>{});
      if (std::find(names.begin(), names.end(), kMeshopt) == names.end()) names.push_back(kMeshopt);
      g[list] = names;
    }
  return g.dump(1) + "\n";
}

}  // namespace

GltfFileSet meshopt_compress_files(const GltfFileSet& in, MeshoptFilesStats* stats) {
  // 1. Parse every file; decide which stay as they are.
  std::map<std::string, json> parsed = parse_files(in);
  const std::set<std::string> kept = kept_files(parsed);

  // 2. Every range each .bin is viewed by, and how.
  Ranges ranges = view_ranges(in, parsed, kept);

  // 3. The new .bin files.
  GltfFileSet out;
  out.bins = in.bins;
  MeshoptFilesStats st;
  for (auto& [uri, placed] : ranges) {
    const std::string& src = in.bins.at(uri);
    std::string bin = pack_bin(src, placed, st);
    st.bin_bytes_before += src.size();
    st.bin_bytes_after += bin.size();
    out.bins[uri] = std::move(bin);
  }

  // 4. Each file's views and buffers pointed at the new .bin files.
  for (auto& [name, g] : parsed)
    out.gltf[name] = kept.count(name) ? in.gltf.at(name) : repoint(g, in, ranges, out.bins);
  if (stats) *stats = st;
  return out;
}

}  // namespace sylva::gltf
