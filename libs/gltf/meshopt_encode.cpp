// EXT_meshopt_compression (the format gltfpack writes), with Debian's meshoptimizer codecs. The
// JSON comes from tinygltf (its buffers left empty) and is patched with nlohmann::json, whose
// sorted keys keep the bytes deterministic, its numbers printed as short as their floats
// (json_numbers.h); the GLB container is assembled here because tinygltf
// cannot write a buffer without data (the fallback buffer).
#include "libs/gltf/meshopt_encode.h"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <cstdint>
#include <cstring>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>
#include <vector>

#include "libs/gltf/json_numbers.h"
#include "libs/gltf/writer.h"

namespace sylva::gltf::detail {

namespace {

constexpr const char* kMeshopt = "EXT_meshopt_compression";

enum class Kind { kRaw, kAttributes, kTriangles, kIndices };

struct ViewUse {
  Kind kind = Kind::kRaw;
  std::size_t count = 0, stride = 0;
  int component_type = 0, type = 0;
};

void pad4(std::string& s, char fill) {
  while (s.size() % 4 != 0) s.push_back(fill);
}

void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

// How each buffer view is used: one accessor of a primitive attribute or of indices, whole
// (count x element size == byteLength), else raw.
std::vector<ViewUse> classify(const tinygltf::Model& m) {
  std::vector<ViewUse> uses(m.bufferViews.size());
  std::vector<int> refs(m.bufferViews.size(), 0);
  for (const auto& a : m.accessors)
    if (a.bufferView >= 0) ++refs[std::size_t(a.bufferView)];
  auto element_size = [](const tinygltf::Accessor& a) {
    return std::size_t(tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType)) *
                       tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)));
  };
  auto mark = [&](int accessor, Kind kind) {
    if (accessor < 0) return;
    const tinygltf::Accessor& a = m.accessors[std::size_t(accessor)];
    if (a.bufferView < 0 || refs[std::size_t(a.bufferView)] != 1 || a.byteOffset != 0 || a.sparse.isSparse)
      return;
    const tinygltf::BufferView& v = m.bufferViews[std::size_t(a.bufferView)];
    // Quantised attributes are padded to a stride of 4 or 8 bytes (xyz of 2-byte components
    // in 8): the element the codecs see is the stride.
    const std::size_t size = v.byteStride != 0 ? v.byteStride : element_size(a);
    if (v.byteStride != 0 && v.byteStride < element_size(a)) return;
    if (a.count == 0 || a.count * size != v.byteLength) return;
    // The vertex codec needs a multiple of 4 bytes per element; the index codec 2- or 4-byte
    // indices, whole triangles.
    if (kind == Kind::kAttributes && (size % 4 != 0 || size > 252)) return;
    if (kind != Kind::kAttributes && size != 2 && size != 4) return;
    if (kind == Kind::kTriangles && a.count % 3 != 0) kind = Kind::kIndices;
    uses[std::size_t(a.bufferView)] = {kind, a.count, size, a.componentType, a.type};
  };
  for (const auto& mesh : m.meshes)
    for (const auto& p : mesh.primitives) {
      for (const auto& [name, acc] : p.attributes) mark(acc, Kind::kAttributes);
      mark(p.indices, p.mode == TINYGLTF_MODE_TRIANGLES ? Kind::kTriangles : Kind::kIndices);
    }
  for (const auto& n : m.nodes) {
    const auto it = n.extensions.find("EXT_mesh_gpu_instancing");
    if (it == n.extensions.end() || !it->second.Has("attributes")) continue;
    const tinygltf::Value& attrs = it->second.Get("attributes");
    for (const std::string& k : attrs.Keys()) mark(attrs.Get(k).GetNumberAsInt(), Kind::kAttributes);
  }
  return uses;
}

std::vector<unsigned int> read_indices(const unsigned char* p, const ViewUse& u) {
  std::vector<unsigned int> out(u.count);
  for (std::size_t i = 0; i < u.count; ++i) {
    if (u.stride == 2) {
      std::uint16_t v;
      std::memcpy(&v, p + 2 * i, 2);
      out[i] = v;
    } else {
      std::memcpy(&out[i], p + 4 * i, 4);
    }
  }
  return out;
}

std::string encode_view(const unsigned char* data, const ViewUse& u) {
  const MeshoptMode mode = u.kind == Kind::kAttributes  ? MeshoptMode::kAttributes
                           : u.kind == Kind::kTriangles ? MeshoptMode::kTriangles
                                                        : MeshoptMode::kIndices;
  return encode_meshopt_view(data, mode, u.count, u.stride);
}

// Views of one kind, element (stride, component type, type) and filter become one view, their
// bytes concatenated in view order, each accessor at its old view's offset in it: one codec
// stream and one JSON view per kind (gltfpack's layout). Index views merge only with views of
// the same primitive mode and index size. Raw views (images) keep their order after the merged
// ones that precede them. Rewrites `model` (views, buffer 0, accessors, images) and returns the
// new views' uses and filters.
void merge_views(tinygltf::Model& model, std::vector<ViewUse>& uses, std::map<int, std::string>& filters) {
  if (model.buffers.empty()) return;
  const std::vector<unsigned char>& src = model.buffers[0].data;
  using Key = std::tuple<int, std::size_t, int, int, std::string>;
  std::map<Key, std::size_t> group_of;  // key -> new view
  std::vector<tinygltf::BufferView> views;
  std::vector<ViewUse> new_uses;
  std::map<int, std::string> new_filters;
  std::vector<unsigned char> data;
  std::vector<std::pair<std::size_t, std::size_t>> moved(model.bufferViews.size());  // new view, offset
  std::vector<std::vector<std::size_t>> members;
  for (std::size_t v = 0; v < model.bufferViews.size(); ++v) {
    const auto f = filters.find(int(v));
    const std::string filter = f == filters.end() ? std::string() : f->second;
    if (uses[v].kind == Kind::kRaw) {
      moved[v] = {views.size(), 0};
      views.push_back(model.bufferViews[v]);
      new_uses.push_back(uses[v]);
      members.push_back({v});
      if (!filter.empty()) new_filters[int(views.size() - 1)] = filter;
      continue;
    }
    const Key key{int(uses[v].kind), uses[v].stride, uses[v].component_type, uses[v].type, filter};
    const auto [it, fresh] = group_of.emplace(key, views.size());
    if (fresh) {
      views.push_back(model.bufferViews[v]);
      views.back().byteLength = 0;
      new_uses.push_back(uses[v]);
      new_uses.back().count = 0;
      members.emplace_back();
      if (!filter.empty()) new_filters[int(views.size() - 1)] = filter;
    }
    moved[v] = {it->second, views[it->second].byteLength};
    views[it->second].byteLength += model.bufferViews[v].byteLength;
    new_uses[it->second].count += uses[v].count;
    members[it->second].push_back(v);
  }
  for (std::size_t n = 0; n < views.size(); ++n) {
    while (data.size() % 4 != 0) data.push_back(0);
    const std::size_t start = data.size();
    for (const std::size_t v : members[n]) {
      const tinygltf::BufferView& old = model.bufferViews[v];
      data.insert(data.end(), src.begin() + std::ptrdiff_t(old.byteOffset),
                  src.begin() + std::ptrdiff_t(old.byteOffset + old.byteLength));
    }
    views[n].byteOffset = start;
  }
  for (auto& a : model.accessors)
    if (a.bufferView >= 0) {
      const auto [view, offset] = moved[std::size_t(a.bufferView)];
      a.bufferView = int(view);
      a.byteOffset += offset;
    }
  for (auto& im : model.images)
    if (im.bufferView >= 0) im.bufferView = int(moved[std::size_t(im.bufferView)].first);
  model.bufferViews = std::move(views);
  model.buffers[0].data = std::move(data);
  uses = std::move(new_uses);
  filters = std::move(new_filters);
}

}  // namespace

std::string encode_meshopt_view(const unsigned char* data, MeshoptMode mode, std::size_t count,
                                std::size_t stride) {
  // Index codec version 1 (EXT_meshopt_compression decoders read 0 and 1); meshoptimizer keeps
  // the choice in a global, set once.
  static std::once_flag once;
  std::call_once(once, [] { meshopt_encodeIndexVersion(1); });
  ViewUse u;
  u.count = count;
  u.stride = stride;
  std::vector<unsigned char> out;
  std::size_t n = 0;
  switch (mode) {
    case MeshoptMode::kAttributes:
      out.resize(meshopt_encodeVertexBufferBound(u.count, u.stride));
      n = meshopt_encodeVertexBuffer(out.data(), out.size(), data, u.count, u.stride);
      break;
    case MeshoptMode::kTriangles: {
      const std::vector<unsigned int> idx = read_indices(data, u);
      unsigned int max_index = 0;
      for (unsigned int i : idx) max_index = std::max(max_index, i);
      out.resize(meshopt_encodeIndexBufferBound(idx.size(), std::size_t(max_index) + 1));
      n = meshopt_encodeIndexBuffer(out.data(), out.size(), idx.data(), idx.size());
      break;
    }
    case MeshoptMode::kIndices: {
      const std::vector<unsigned int> idx = read_indices(data, u);
      unsigned int max_index = 0;
      for (unsigned int i : idx) max_index = std::max(max_index, i);
      out.resize(meshopt_encodeIndexSequenceBound(idx.size(), std::size_t(max_index) + 1));
      n = meshopt_encodeIndexSequence(out.data(), out.size(), idx.data(), idx.size());
      break;
    }
  }
  if (n == 0) throw GltfError("meshoptimizer could not encode a buffer view");
  return std::string(reinterpret_cast<const char*>(out.data()), n);
}

namespace {

// The model's JSON as tinygltf writes it, without the buffers' data (tinygltf would base64 it);
// the buffers are rewritten afterwards.
nlohmann::json json_without_data(tinygltf::Model& model) {
  for (auto& b : model.buffers) b.data.assign(4, 0);
  tinygltf::TinyGLTF writer;
  std::ostringstream text;
  if (!writer.WriteGltfSceneToStream(&model, text, /*prettyPrint=*/false, /*writeBinary=*/false))
    throw GltfError("tinygltf could not serialise the scene");
  return nlohmann::json::parse(std::move(text).str());
}

// The binary chunk: each view's bytes, compressed unless kRaw; and the fallback buffer's size.
struct BinaryChunk {
  std::string bin;
  std::size_t fallback = 0;
  bool any = false;  // a view was compressed
};

// Writes every view into the chunk, in view order, and points its JSON (j["bufferViews"]) at it:
// a raw view at its offset in buffer 0, a compressed one at the fallback buffer, with the
// extension's object naming the compressed bytes.
BinaryChunk compress_views(const tinygltf::Model& model, const std::vector<ViewUse>& uses,
                           const std::map<int, std::string>& filters,
                           const std::vector<unsigned char>& source, nlohmann::json& j) {
  BinaryChunk out;
  std::string& bin = out.bin;
  for (std::size_t v = 0; v < model.bufferViews.size(); ++v) {
    const tinygltf::BufferView& view = model.bufferViews[v];
    nlohmann::json& jv = j["bufferViews"][v];
    if (view.buffer != 0 || view.byteOffset + view.byteLength > source.size())
      throw GltfError("meshopt: a buffer view lies outside the scene's buffer");
    const unsigned char* data = source.data() + view.byteOffset;
    pad4(bin, '\0');
    const auto filter = filters.find(static_cast<int>(v));
    if (uses[v].kind == Kind::kRaw) {
      if (filter != filters.end())
        throw GltfError("meshopt: buffer view " + std::to_string(v) +
                        " is filtered but cannot be compressed");
      jv["byteOffset"] = bin.size();
      bin.append(reinterpret_cast<const char*>(data), view.byteLength);
      continue;
    }
    const std::string enc = encode_view(data, uses[v]);
    const char* mode = uses[v].kind == Kind::kAttributes  ? "ATTRIBUTES"
                       : uses[v].kind == Kind::kTriangles ? "TRIANGLES"
                                                          : "INDICES";
    jv[std::string("extensions")][kMeshopt] = {{"buffer", 0},
                                               {"byteOffset", bin.size()},
                                               {"byteLength", enc.size()},
                                               {"byteStride", uses[v].stride},
                                               {"count", uses[v].count},
                                               {"mode", mode}};
    if (filter != filters.end()) jv["extensions"][kMeshopt]["filter"] = filter->second;
    bin += enc;
    jv["buffer"] = 1;
    jv["byteOffset"] = out.fallback;
    if (uses[v].kind == Kind::kAttributes) jv["byteStride"] = uses[v].stride;
    out.fallback += (view.byteLength + 3) / 4 * 4;
    out.any = true;
  }
  pad4(bin, '\0');
  return out;
}

// The JSON's buffers: the chunk (when not empty), then the fallback buffer (when a view was
// compressed, which also lists the extension as used and required).
void list_buffers(nlohmann::json& j, const BinaryChunk& chunk) {
  j["buffers"] = nlohmann::json::array();
  if (!chunk.bin.empty()) j["buffers"].push_back({{"byteLength", chunk.bin.size()}});
  if (chunk.any) {
    j["buffers"].push_back(
        {{"byteLength", chunk.fallback}, {"extensions", {{kMeshopt, {{"fallback", true}}}}}});
    for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
      std::vector<std::string> names = j.value(list, std::vector<std::string>{});
      names.push_back(kMeshopt);
      std::sort(names.begin(), names.end());
      names.erase(std::unique(names.begin(), names.end()), names.end());
      j[list] = names;
    }
  }
  if (chunk.bin.empty() && !chunk.any) j.erase("buffers");
}

// GLB framing: header, JSON chunk (space padded), BIN chunk when there are bytes.
std::string glb_file(std::string json_text, const std::string& bin) {
  pad4(json_text, ' ');
  std::string glb;
  const std::size_t total = 12 + 8 + json_text.size() + (bin.empty() ? 0 : 8 + bin.size());
  if (total > 0xFFFFFFFFu) throw GltfError("meshopt: the GLB would exceed 4 GiB");
  glb.reserve(total);
  glb += "glTF";
  put_u32(glb, 2);
  put_u32(glb, static_cast<std::uint32_t>(total));
  put_u32(glb, static_cast<std::uint32_t>(json_text.size()));
  glb += "JSON";
  glb += json_text;
  if (!bin.empty()) {
    put_u32(glb, static_cast<std::uint32_t>(bin.size()));
    glb += std::string("BIN\0", 4);
    glb += bin;
  }
  return glb;
}

}  // namespace

std::string encode_meshopt_glb(tinygltf::Model& model, const std::map<int, std::string>& view_filters,
                               bool merge) {
  std::vector<ViewUse> uses = classify(model);
  std::map<int, std::string> filters = view_filters;
  if (merge) merge_views(model, uses, filters);
  std::vector<unsigned char> source;
  if (!model.buffers.empty()) source.swap(model.buffers[0].data);
  nlohmann::json j = json_without_data(model);
  const BinaryChunk chunk = compress_views(model, uses, filters, source, j);
  list_buffers(j, chunk);
  compact_gltf_numbers(j);  // floats printed as floats (json_numbers.h)
  return glb_file(j.dump(), chunk.bin);
}

}  // namespace sylva::gltf::detail
