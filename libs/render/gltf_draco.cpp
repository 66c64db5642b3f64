// Draco in glTF (gltf_draco.h).
#include "libs/render/gltf_draco.h"

#include <draco/compression/decode.h>

#include <memory>
#include <nlohmann/json.hpp>

namespace sylva::render::detail {
namespace {

std::uint32_t le32(const std::string& b, std::size_t at) {
  return std::uint32_t(std::uint8_t(b[at])) | std::uint32_t(std::uint8_t(b[at + 1])) << 8 |
         std::uint32_t(std::uint8_t(b[at + 2])) << 16 | std::uint32_t(std::uint8_t(b[at + 3])) << 24;
}

void put_le32(std::string& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + std::size_t(i)] = char((v >> (8 * i)) & 0xff);
}

}  // namespace

DracoData decode_draco(const GltfModel& in, const tinygltf::Value& ext, const std::string& what) {
  const tinygltf::Model& model = in.model();
  if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Has("attributes"))
    in.fail(what + ": " + kDraco + " needs 'bufferView' and 'attributes'");
  const int view = ext.Get("bufferView").GetNumberAsInt();
  if (view < 0 || std::size_t(view) >= model.bufferViews.size())
    in.fail(what + ": Draco buffer view " + std::to_string(view) + " does not exist");
  const std::size_t len = model.bufferViews[std::size_t(view)].byteLength;
  const unsigned char* data = in.view_data(view, 0, 1, len, len, what);

  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(data), len);
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) in.fail(what + ": cannot decode Draco data: " + type.status().error_msg_string());
  draco::Decoder decoder;
  std::unique_ptr<draco::PointCloud> cloud;
  DracoData out;
  if (type.value() == draco::TRIANGULAR_MESH) {
    auto mesh = decoder.DecodeMeshFromBuffer(&buffer);
    if (!mesh.ok()) in.fail(what + ": cannot decode Draco mesh: " + mesh.status().error_msg_string());
    std::unique_ptr<draco::Mesh> dm = std::move(mesh).value();
    out.has_faces = true;
    out.indices.reserve(std::size_t(dm->num_faces()) * 3);
    for (draco::FaceIndex f(0); f < dm->num_faces(); ++f)
      for (int k = 0; k < 3; ++k) out.indices.push_back(dm->face(f)[k].value());
    cloud = std::move(dm);
  } else if (type.value() == draco::POINT_CLOUD) {
    auto pc = decoder.DecodePointCloudFromBuffer(&buffer);
    if (!pc.ok()) in.fail(what + ": cannot decode Draco point cloud: " + pc.status().error_msg_string());
    cloud = std::move(pc).value();
  } else {
    in.fail(what + ": unknown Draco geometry type");
  }
  const tinygltf::Value& attrs = ext.Get("attributes");
  for (const std::string& name : attrs.Keys()) {
    const int uid = attrs.Get(name).GetNumberAsInt();
    const draco::PointAttribute* pa = cloud->GetAttributeByUniqueId(std::uint32_t(uid));
    if (!pa) in.fail(what + ": Draco attribute " + name + " (id " + std::to_string(uid) + ") is missing");
    AttributeData a;
    a.components = pa->num_components();
    a.count = cloud->num_points();
    a.values.resize(a.count * std::size_t(a.components));
    for (draco::PointIndex i(0); i < cloud->num_points(); ++i) {
      if (!pa->ConvertValue<float>(pa->mapped_index(i), std::int8_t(a.components),
                                   &a.values[std::size_t(i.value()) * std::size_t(a.components)]))
        in.fail(what + ": Draco attribute " + name + " cannot be converted to float");
    }
    out.attributes.emplace(name, std::move(a));
  }
  return out;
}

std::optional<std::string> without_draco_index_accessors(const std::string& text) {
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_discarded() || !doc.is_object() || !doc.contains("meshes") || !doc["meshes"].is_array())
    return std::nullopt;
  const nlohmann::json* accessors =
      doc.contains("accessors") && doc["accessors"].is_array() ? &doc["accessors"] : nullptr;
  bool changed = false;
  for (auto& mesh : doc["meshes"]) {
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (auto& prim : mesh["primitives"]) {
      if (!prim.is_object() || !prim.contains("indices") || !prim["indices"].is_number_integer()) continue;
      if (!prim.contains("extensions") || !prim["extensions"].is_object() ||
          !prim["extensions"].contains(kDraco))
        continue;
      const auto index = prim["indices"].get<long long>();
      if (!accessors || index < 0 || std::size_t(index) >= accessors->size()) continue;
      const nlohmann::json& acc = (*accessors)[std::size_t(index)];
      if (acc.is_object() && acc.contains("bufferView")) continue;
      prim.erase("indices");
      changed = true;
    }
  }
  if (!changed) return std::nullopt;
  return doc.dump();
}

void patch_glb(std::string& bytes) {
  if (bytes.size() < 20 || le32(bytes, 16) != 0x4E4F534Au) return;  // first chunk must be JSON
  const std::size_t json_len = le32(bytes, 12);
  if (20 + json_len > bytes.size()) return;
  auto patched = without_draco_index_accessors(bytes.substr(20, json_len));
  if (!patched) return;
  while (patched->size() % 4) *patched += ' ';
  std::string out = bytes.substr(0, 12);
  out.resize(20);
  put_le32(out, 12, std::uint32_t(patched->size()));
  put_le32(out, 16, 0x4E4F534Au);
  out += *patched;
  out += bytes.substr(20 + json_len);
  put_le32(out, 8, std::uint32_t(out.size()));
  bytes = std::move(out);
}

}  // namespace sylva::render::detail
