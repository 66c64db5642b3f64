#include "libs/render/meshopt_decode.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <vector>

namespace sylva::render {

namespace {

constexpr const char* kExt = "EXT_meshopt_compression";

std::uint32_t le32(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

void put_u32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

bool uses_meshopt(const nlohmann::json& j) {
  if (!j.contains("extensionsUsed") || !j["extensionsUsed"].is_array()) return false;
  for (const auto& e : j["extensionsUsed"])
    if (e == kExt) return true;
  return false;
}

std::string glb_of(const std::string& json_text, const std::string& bin) {
  std::string text = json_text;
  while (text.size() % 4) text.push_back(' ');
  std::string glb = "glTF";
  put_u32(glb, 2);
  put_u32(glb, static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
  put_u32(glb, static_cast<std::uint32_t>(text.size()));
  glb += "JSON";
  glb += text;
  put_u32(glb, static_cast<std::uint32_t>(bin.size()));
  glb += std::string("BIN\0", 4);
  glb += bin;
  return glb;
}

}  // namespace

std::optional<std::string> meshopt_gltf_as_glb(
    const std::string& json_text, const std::function<std::string(const std::string&)>& read_uri) {
  if (json_text.find(kExt) == std::string::npos) return std::nullopt;
  nlohmann::json j = nlohmann::json::parse(json_text, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !uses_meshopt(j) || !j.contains("buffers") ||
      !j["buffers"].is_array())
    return std::nullopt;
  // Buffers with a file uri go into the binary chunk (new buffer 0) at `shift`; the others
  // (fallbacks, data: uris) keep their order after it.
  nlohmann::json& buffers = j["buffers"];
  std::string bin;
  struct Move {
    std::size_t buffer, shift;
  };
  std::vector<Move> moves(buffers.size());
  nlohmann::json kept = nlohmann::json::array({nlohmann::json::object()});
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    const nlohmann::json& buf = buffers[b];
    const std::string uri = buf.is_object() ? buf.value("uri", std::string()) : std::string();
    if (uri.empty() || uri.rfind("data:", 0) == 0) {
      moves[b] = {kept.size(), 0};
      kept.push_back(buf);
      continue;
    }
    const std::size_t length = buf.value("byteLength", std::size_t(0));
    std::string bytes = read_uri(uri);
    if (bytes.size() < length)
      throw std::runtime_error("buffer " + std::to_string(b) + " ('" + uri.substr(0, 64) + "') has " +
                               std::to_string(bytes.size()) + " bytes, byteLength says " +
                               std::to_string(length));
    while (bin.size() % 4) bin.push_back('\0');
    moves[b] = {0, bin.size()};
    bin.append(bytes, 0, length);
  }
  while (bin.size() % 4) bin.push_back('\0');
  kept[0]["byteLength"] = bin.size();
  auto move = [&](nlohmann::json& ref) {
    const std::size_t b = ref.value("buffer", std::size_t(0));
    if (b >= moves.size()) return;  // tinygltf reports the bad index
    ref["buffer"] = moves[b].buffer;
    if (moves[b].shift) ref["byteOffset"] = ref.value("byteOffset", std::size_t(0)) + moves[b].shift;
  };
  if (j.contains("bufferViews") && j["bufferViews"].is_array())
    for (auto& view : j["bufferViews"]) {
      if (!view.is_object()) continue;
      move(view);
      if (view.contains("extensions") && view["extensions"].is_object() &&
          view["extensions"].contains(kExt) && view["extensions"][kExt].is_object())
        move(view["extensions"][kExt]);
    }
  j["buffers"] = kept;
  return glb_of(j.dump(), bin);
}

namespace {

// The GLB's BIN chunk (empty when it has none); the JSON chunk ends at `bin_at`.
std::string binary_chunk(const std::string& bytes, std::size_t bin_at) {
  if (bin_at + 8 <= bytes.size() && le32(bytes, bin_at + 4) == 0x004E4942u) {
    const std::size_t n = le32(bytes, bin_at);
    if (bin_at + 8 + n > bytes.size())
      throw std::runtime_error("EXT_meshopt_compression: truncated binary chunk");
    return bytes.substr(bin_at + 8, n);
  }
  return {};
}

// The decoded bytes of view `v`, whose extension object is `e`: the codec its mode names, then
// the filter. Only buffer 0 (the binary chunk `bin`) may hold data here: the decoder reads
// compressed bytes from it.
std::string decode_view(const nlohmann::json& e, const std::string& bin, std::size_t v) {
  const std::size_t count = e.value("count", std::size_t(0)), stride = e.value("byteStride", std::size_t(0));
  const std::size_t size = e.value("byteLength", std::size_t(0));
  const std::string mode = e.value("mode", std::string()), filter = e.value("filter", std::string("NONE"));
  if (count == 0 || stride == 0 || stride > 256)
    throw std::runtime_error("EXT_meshopt_compression: bad count or stride");
  std::string out(count * stride, '\0');
  const std::size_t b = e.value("buffer", std::size_t(0)), off = e.value("byteOffset", std::size_t(0)),
                    len = e.value("byteLength", std::size_t(0));
  if (b != 0 || off + len > bin.size())
    throw std::runtime_error("EXT_meshopt_compression: data outside the binary chunk");
  const unsigned char* src = reinterpret_cast<const unsigned char*>(bin.data()) + off;
  int rc = -1;
  if (mode == "ATTRIBUTES")
    rc = meshopt_decodeVertexBuffer(out.data(), count, stride, src, size);
  else if (mode == "TRIANGLES")
    rc = meshopt_decodeIndexBuffer(out.data(), count, stride, src, size);
  else if (mode == "INDICES")
    rc = meshopt_decodeIndexSequence(out.data(), count, stride, src, size);
  else
    throw std::runtime_error("EXT_meshopt_compression: unknown mode '" + mode.substr(0, 32) + "'");
  if (rc != 0)
    throw std::runtime_error("EXT_meshopt_compression: buffer view " + std::to_string(v) +
                             " does not decode");
  if (filter == "OCTAHEDRAL")
    meshopt_decodeFilterOct(out.data(), count, stride);
  else if (filter == "QUATERNION")
    meshopt_decodeFilterQuat(out.data(), count, stride);
  else if (filter == "EXPONENTIAL")
    meshopt_decodeFilterExp(out.data(), count, stride);
  else if (filter != "NONE")
    throw std::runtime_error("EXT_meshopt_compression: unknown filter '" + filter.substr(0, 32) + "'");
  return out;
}

// Fallback buffers (no data) go, every view of them having been decoded; buffer 0 (the binary
// chunk) gets `bin_length` bytes and the views are renumbered.
void drop_fallback_buffers(nlohmann::json& j, std::size_t bin_length) {
  nlohmann::json& buffers = j["buffers"];
  nlohmann::json& views = j["bufferViews"];
  std::vector<int> remap(buffers.size(), -1);
  nlohmann::json kept = nlohmann::json::array();
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    const bool fallback = buffers[b].contains("extensions") && buffers[b]["extensions"].contains(kExt) &&
                          buffers[b]["extensions"][kExt].value("fallback", false);
    if (fallback && b != 0) continue;
    remap[b] = static_cast<int>(kept.size());
    kept.push_back(buffers[b]);
  }
  if (kept.empty()) kept.push_back(nlohmann::json::object());
  kept[0]["byteLength"] = bin_length;
  for (auto& view : views) {
    const std::size_t b = view.value("buffer", std::size_t(0));
    if (b >= remap.size() || remap[b] < 0)
      throw std::runtime_error("EXT_meshopt_compression: a view of a fallback buffer is not compressed");
    view["buffer"] = remap[b];
  }
  j["buffers"] = kept;
}

}  // namespace

bool decode_meshopt_glb(std::string& bytes) {
  if (bytes.size() < 20 || le32(bytes, 16) != 0x4E4F534Au) return false;
  const std::size_t json_len = le32(bytes, 12);
  if (20 + json_len > bytes.size()) return false;
  const std::string json_text = bytes.substr(20, json_len);
  if (json_text.find(kExt) == std::string::npos) return false;
  nlohmann::json j = nlohmann::json::parse(json_text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return false;
  std::string bin = binary_chunk(bytes, 20 + json_len);
  if (!j.contains("buffers") || !j["buffers"].is_array())
    throw std::runtime_error("EXT_meshopt_compression: no buffers");
  // Each compressed view decodes into one run of bytes appended to the binary chunk.
  std::string decoded_all;
  std::vector<std::pair<std::size_t, std::size_t>> placed;  // (view, offset in decoded_all)
  nlohmann::json& views = j["bufferViews"];
  for (std::size_t v = 0; v < views.size(); ++v) {
    nlohmann::json& view = views[v];
    if (!view.contains("extensions") || !view["extensions"].contains(kExt)) continue;
    const std::string out = decode_view(view["extensions"][kExt], bin, v);
    while (decoded_all.size() % 4) decoded_all.push_back('\0');
    placed.emplace_back(v, decoded_all.size());
    decoded_all += out;
    view["byteLength"] = out.size();
    view["extensions"].erase(kExt);
    if (view["extensions"].empty()) view.erase("extensions");
  }
  while (bin.size() % 4) bin.push_back('\0');
  const std::size_t base = bin.size();
  for (const auto& [v, off] : placed) {
    views[v]["buffer"] = 0;
    views[v]["byteOffset"] = base + off;
  }
  bin += decoded_all;
  const std::size_t bin_length = bin.size();
  while (bin.size() % 4) bin.push_back('\0');  // a GLB chunk ends on a 4-byte boundary
  drop_fallback_buffers(j, bin_length);
  for (const char* list : {"extensionsUsed", "extensionsRequired"})
    if (j.contains(list) && j[list].is_array()) {
      nlohmann::json names = nlohmann::json::array();
      for (const auto& n : j[list])
        if (n != kExt) names.push_back(n);
      j[list] = names;
      if (names.empty()) j.erase(list);
    }
  bytes = glb_of(j.dump(), bin);
  return true;
}

}  // namespace sylva::render
