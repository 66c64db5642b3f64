// KHR_draco_mesh_compression encoding of one TRIANGLES primitive with the Draco library.
//
// The Draco mesh gets one point per glTF vertex (identity attribute mapping, so no value is
// merged or reordered before the encoder sees it) and one face per triangle. The edgebreaker
// encoder may still split vertices where the connectivity is not manifold; the counts the
// decoder will return are taken from the encoder (num_encoded_points/faces), which is what the
// accessors must declare.
#include "libs/gltf/draco_encode.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <algorithm>
#include <memory>

namespace sylva::gltf::detail {
namespace {

// Adds a float attribute with `comps` components per point; returns the attribute.
draco::PointAttribute* add_attribute(draco::Mesh& mesh, draco::GeometryAttribute::Type type, int comps,
                                     const std::vector<float>& values, std::size_t points) {
  draco::GeometryAttribute ga;
  ga.Init(type, nullptr, static_cast<std::uint8_t>(comps), draco::DT_FLOAT32, false,
          static_cast<std::int64_t>(sizeof(float) * static_cast<std::size_t>(comps)), 0);
  const int id = mesh.AddAttribute(ga, true, static_cast<std::uint32_t>(points));
  draco::PointAttribute* att = mesh.attribute(id);
  for (std::size_t i = 0; i < points; ++i)
    att->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(i)),
                           values.data() + i * static_cast<std::size_t>(comps));
  return att;
}

int clamp_bits(int b) { return std::clamp(b, 1, 30); }

}  // namespace

DracoEncoded encode_draco(const Primitive& p, const DracoOptions& options, bool with_tangents) {
  const std::size_t points = p.vertex_count();
  draco::Mesh mesh;
  mesh.set_num_points(static_cast<std::uint32_t>(points));
  const std::size_t corners = p.indices.empty() ? points : p.indices.size();
  for (std::size_t i = 0; i + 2 < corners; i += 3) {
    draco::Mesh::Face f;
    for (int k = 0; k < 3; ++k) {
      const std::size_t c = i + static_cast<std::size_t>(k);
      f[k] = draco::PointIndex(p.indices.empty() ? static_cast<std::uint32_t>(c) : p.indices[c]);
    }
    mesh.AddFace(f);
  }

  DracoEncoded out;
  auto add = [&](const char* name, draco::GeometryAttribute::Type type, int comps,
                 const std::vector<float>& v) {
    if (v.empty()) return;
    const draco::PointAttribute* att = add_attribute(mesh, type, comps, v, points);
    out.attribute_ids.emplace_back(name, static_cast<int>(att->unique_id()));
  };
  add("POSITION", draco::GeometryAttribute::POSITION, 3, p.positions);
  add("NORMAL", draco::GeometryAttribute::NORMAL, 3, p.normals);
  if (with_tangents) add("TANGENT", draco::GeometryAttribute::GENERIC, 4, p.tangents);
  add("TEXCOORD_0", draco::GeometryAttribute::TEX_COORD, 2, p.texcoords);
  add("COLOR_0", draco::GeometryAttribute::COLOR, 4, p.colors);
  std::vector<const CustomAttribute*> custom;
  for (const CustomAttribute& a : p.custom) custom.push_back(&a);
  std::sort(custom.begin(), custom.end(), [](auto* a, auto* b) { return a->name < b->name; });
  for (const CustomAttribute* a : custom)
    add(a->name.c_str(), draco::GeometryAttribute::GENERIC, a->components, a->values);

  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, clamp_bits(options.position_bits));
  encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, clamp_bits(options.normal_bits));
  encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, clamp_bits(options.texcoord_bits));
  encoder.SetAttributeQuantization(draco::GeometryAttribute::COLOR, clamp_bits(options.color_bits));
  encoder.SetAttributeQuantization(draco::GeometryAttribute::GENERIC, clamp_bits(options.generic_bits));
  const int speed = 10 - std::clamp(options.compression_level, 0, 10);
  encoder.SetSpeedOptions(speed, speed);
  encoder.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
  encoder.SetTrackEncodedProperties(true);
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeMeshToBuffer(mesh, &buffer);
  if (!status.ok()) throw GltfError(std::string("Draco encoding failed: ") + status.error_msg());
  out.bytes.assign(buffer.data(), buffer.size());
  out.points = encoder.num_encoded_points();
  out.faces = encoder.num_encoded_faces();
  return out;
}

}  // namespace sylva::gltf::detail
