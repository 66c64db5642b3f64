#include "libs/render/testing/gltf_builder.h"

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "libs/image/png.h"

namespace sylva::render::testing {

GltfBuilder::GltfBuilder() {
  model_.asset.version = "2.0";
  model_.asset.generator = "sylva tests";
  model_.buffers.emplace_back();
  model_.scenes.emplace_back();
  model_.defaultScene = 0;
}

int GltfBuilder::add_view(const void* data, std::size_t bytes, int target) {
  auto& buf = model_.buffers[0].data;
  while (buf.size() % 4) buf.push_back(0);
  tinygltf::BufferView v;
  v.buffer = 0;
  v.byteOffset = buf.size();
  v.byteLength = bytes;
  v.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buf.insert(buf.end(), p, p + bytes);
  model_.bufferViews.push_back(v);
  return int(model_.bufferViews.size() - 1);
}

int GltfBuilder::add_accessor(const void* data, std::size_t count, int type, int component_type, int target,
                              bool min_max) {
  const int comps = tinygltf::GetNumComponentsInType(std::uint32_t(type));
  const int csize = tinygltf::GetComponentSizeInBytes(std::uint32_t(component_type));
  tinygltf::Accessor a;
  a.bufferView = data ? add_view(data, count * std::size_t(comps * csize), target) : -1;
  a.count = count;
  a.type = type;
  a.componentType = component_type;
  if (min_max && component_type == TINYGLTF_COMPONENT_TYPE_FLOAT && data) {
    const auto* f = static_cast<const float*>(data);
    a.minValues.assign(std::size_t(comps), 1e30);
    a.maxValues.assign(std::size_t(comps), -1e30);
    for (std::size_t i = 0; i < count; ++i)
      for (int c = 0; c < comps; ++c) {
        a.minValues[std::size_t(c)] =
            std::min(a.minValues[std::size_t(c)], double(f[i * std::size_t(comps) + std::size_t(c)]));
        a.maxValues[std::size_t(c)] =
            std::max(a.maxValues[std::size_t(c)], double(f[i * std::size_t(comps) + std::size_t(c)]));
      }
  }
  model_.accessors.push_back(a);
  return int(model_.accessors.size() - 1);
}

int GltfBuilder::add_texture(const image::Image& img, bool nearest) {
  const std::vector<std::uint8_t> png = image::encode_png(img);
  tinygltf::Image gi;
  gi.bufferView = add_view(png.data(), png.size(), 0);
  gi.mimeType = "image/png";
  model_.images.push_back(gi);
  tinygltf::Sampler s;
  s.magFilter = nearest ? TINYGLTF_TEXTURE_FILTER_NEAREST : TINYGLTF_TEXTURE_FILTER_LINEAR;
  s.minFilter = nearest ? TINYGLTF_TEXTURE_FILTER_NEAREST : TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  s.wrapS = s.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model_.samplers.push_back(s);
  tinygltf::Texture t;
  t.source = int(model_.images.size() - 1);
  t.sampler = int(model_.samplers.size() - 1);
  model_.textures.push_back(t);
  return int(model_.textures.size() - 1);
}

int GltfBuilder::add_material(const MaterialData& m) {
  tinygltf::Material gm;
  gm.pbrMetallicRoughness.baseColorFactor = {m.base_color[0], m.base_color[1], m.base_color[2],
                                             m.base_color[3]};
  gm.pbrMetallicRoughness.baseColorTexture.index = m.texture;
  gm.pbrMetallicRoughness.metallicFactor = 0.0;
  gm.alphaMode = m.alpha_mode;
  gm.alphaCutoff = m.alpha_cutoff;
  gm.doubleSided = m.double_sided;
  if (m.unlit) {
    gm.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
    if (std::find(model_.extensionsUsed.begin(), model_.extensionsUsed.end(), "KHR_materials_unlit") ==
        model_.extensionsUsed.end())
      model_.extensionsUsed.push_back("KHR_materials_unlit");
  }
  model_.materials.push_back(gm);
  return int(model_.materials.size() - 1);
}

namespace {

void use_extension(tinygltf::Model& m, const std::string& ext, bool required) {
  if (std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(), ext) == m.extensionsUsed.end())
    m.extensionsUsed.push_back(ext);
  if (required &&
      std::find(m.extensionsRequired.begin(), m.extensionsRequired.end(), ext) == m.extensionsRequired.end())
    m.extensionsRequired.push_back(ext);
}

}  // namespace

int GltfBuilder::add_mesh(const std::vector<PrimitiveData>& primitives, const std::string& name) {
  tinygltf::Mesh mesh;
  mesh.name = name;
  for (const PrimitiveData& p : primitives) {
    tinygltf::Primitive gp;
    gp.mode = p.mode;
    gp.material = p.material;
    if (p.draco) {
      // Encode a triangle soup (Draco deduplicates the vertices), then describe the decoded
      // layout with buffer-less accessors as KHR_draco_mesh_compression requires.
      const std::size_t faces = p.indices.size() / 3;
      draco::TriangleSoupMeshBuilder mb;
      mb.Start(int(faces));
      const int pos = mb.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
      const int nrm =
          p.normals.empty() ? -1 : mb.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
      const int uv = p.texcoords.empty()
                         ? -1
                         : mb.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
      for (std::size_t f = 0; f < faces; ++f) {
        const auto i0 = p.indices[f * 3], i1 = p.indices[f * 3 + 1], i2 = p.indices[f * 3 + 2];
        mb.SetAttributeValuesForFace(pos, draco::FaceIndex(std::uint32_t(f)), p.positions[i0].data(),
                                     p.positions[i1].data(), p.positions[i2].data());
        if (nrm >= 0)
          mb.SetAttributeValuesForFace(nrm, draco::FaceIndex(std::uint32_t(f)), p.normals[i0].data(),
                                       p.normals[i1].data(), p.normals[i2].data());
        if (uv >= 0)
          mb.SetAttributeValuesForFace(uv, draco::FaceIndex(std::uint32_t(f)), p.texcoords[i0].data(),
                                       p.texcoords[i1].data(), p.texcoords[i2].data());
      }
      std::unique_ptr<draco::Mesh> dm = mb.Finalize();
      if (!dm) throw std::runtime_error("draco mesh builder failed");
      draco::Encoder enc;
      enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 16);
      enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 12);
      enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 14);
      draco::EncoderBuffer out;
      if (!enc.EncodeMeshToBuffer(*dm, &out).ok()) throw std::runtime_error("draco encoding failed");
      const int view = add_view(out.data(), out.size(), 0);
      const std::size_t points = dm->num_points();
      tinygltf::Value::Object attrs;
      gp.attributes["POSITION"] =
          add_accessor(nullptr, points, TINYGLTF_TYPE_VEC3, TINYGLTF_COMPONENT_TYPE_FLOAT, 0);
      // POSITION needs min/max even without a buffer view.
      model_.accessors.back().minValues = {-1e3, -1e3, -1e3};
      model_.accessors.back().maxValues = {1e3, 1e3, 1e3};
      attrs["POSITION"] = tinygltf::Value(int(dm->attribute(pos)->unique_id()));
      if (nrm >= 0) {
        gp.attributes["NORMAL"] =
            add_accessor(nullptr, points, TINYGLTF_TYPE_VEC3, TINYGLTF_COMPONENT_TYPE_FLOAT, 0);
        attrs["NORMAL"] = tinygltf::Value(int(dm->attribute(nrm)->unique_id()));
      }
      if (uv >= 0) {
        gp.attributes["TEXCOORD_0"] =
            add_accessor(nullptr, points, TINYGLTF_TYPE_VEC2, TINYGLTF_COMPONENT_TYPE_FLOAT, 0);
        attrs["TEXCOORD_0"] = tinygltf::Value(int(dm->attribute(uv)->unique_id()));
      }
      gp.indices = add_accessor(nullptr, std::size_t(dm->num_faces()) * 3, TINYGLTF_TYPE_SCALAR,
                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 0);
      tinygltf::Value::Object ext;
      ext["bufferView"] = tinygltf::Value(view);
      ext["attributes"] = tinygltf::Value(attrs);
      gp.extensions["KHR_draco_mesh_compression"] = tinygltf::Value(ext);
      use_extension(model_, "KHR_draco_mesh_compression", true);
    } else {
      gp.attributes["POSITION"] =
          add_accessor(p.positions.data(), p.positions.size(), TINYGLTF_TYPE_VEC3,
                       TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER, true);
      if (!p.normals.empty())
        gp.attributes["NORMAL"] = add_accessor(p.normals.data(), p.normals.size(), TINYGLTF_TYPE_VEC3,
                                               TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
      if (!p.texcoords.empty())
        gp.attributes["TEXCOORD_0"] =
            add_accessor(p.texcoords.data(), p.texcoords.size(), TINYGLTF_TYPE_VEC2,
                         TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
      if (!p.colors.empty())
        gp.attributes["COLOR_0"] = add_accessor(p.colors.data(), p.colors.size(), TINYGLTF_TYPE_VEC4,
                                                TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
      if (!p.sizes.empty())
        gp.attributes["_SIZE"] = add_accessor(p.sizes.data(), p.sizes.size(), TINYGLTF_TYPE_SCALAR,
                                              TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
      if (!p.indices.empty())
        gp.indices = add_accessor(p.indices.data(), p.indices.size(), TINYGLTF_TYPE_SCALAR,
                                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    }
    mesh.primitives.push_back(gp);
  }
  model_.meshes.push_back(mesh);
  return int(model_.meshes.size() - 1);
}

int GltfBuilder::add_node(const NodeData& n) {
  tinygltf::Node node;
  node.mesh = n.mesh;
  node.children = n.children;
  if (!n.translation.isZero()) node.translation = {n.translation.x(), n.translation.y(), n.translation.z()};
  if (!n.rotation.coeffs().isApprox(Eigen::Quaternionf::Identity().coeffs()))
    node.rotation = {n.rotation.x(), n.rotation.y(), n.rotation.z(), n.rotation.w()};
  if (!n.scale.isOnes()) node.scale = {n.scale.x(), n.scale.y(), n.scale.z()};
  if (!n.instance_translations.empty() || !n.instance_rotations.empty() || !n.instance_scales.empty()) {
    tinygltf::Value::Object attrs;
    if (!n.instance_translations.empty())
      attrs["TRANSLATION"] =
          tinygltf::Value(add_accessor(n.instance_translations.data(), n.instance_translations.size(),
                                       TINYGLTF_TYPE_VEC3, TINYGLTF_COMPONENT_TYPE_FLOAT, 0));
    if (!n.instance_rotations.empty()) {
      std::vector<float> xyzw;
      for (const auto& q : n.instance_rotations) xyzw.insert(xyzw.end(), {q.x(), q.y(), q.z(), q.w()});
      attrs["ROTATION"] = tinygltf::Value(add_accessor(xyzw.data(), n.instance_rotations.size(),
                                                       TINYGLTF_TYPE_VEC4, TINYGLTF_COMPONENT_TYPE_FLOAT, 0));
    }
    if (!n.instance_scales.empty())
      attrs["SCALE"] = tinygltf::Value(add_accessor(n.instance_scales.data(), n.instance_scales.size(),
                                                    TINYGLTF_TYPE_VEC3, TINYGLTF_COMPONENT_TYPE_FLOAT, 0));
    tinygltf::Value::Object ext;
    ext["attributes"] = tinygltf::Value(attrs);
    node.extensions["EXT_mesh_gpu_instancing"] = tinygltf::Value(ext);
    use_extension(model_, "EXT_mesh_gpu_instancing", true);
  }
  model_.nodes.push_back(node);
  return int(model_.nodes.size() - 1);
}

void GltfBuilder::add_root(int node) { model_.scenes[0].nodes.push_back(node); }

void GltfBuilder::write_glb(const std::filesystem::path& path) const {
  tinygltf::TinyGLTF writer;
  tinygltf::Model copy = model_;
  if (copy.buffers[0].data.empty()) copy.buffers.clear();
  if (!writer.WriteGltfSceneToFile(&copy, path.string(), true, true, false, true))
    throw std::runtime_error("cannot write " + path.string());
}

PrimitiveData quad(float size, int material) {
  const float h = size * 0.5f;
  PrimitiveData p;
  p.positions = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  p.normals.assign(4, Vec3(0, 0, 1));
  p.texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  p.indices = {0, 1, 2, 0, 2, 3};
  p.material = material;
  return p;
}

PrimitiveData cube(float size, int material) {
  PrimitiveData p;
  p.material = material;
  const float h = size * 0.5f;
  // For each face: normal, and the two in-plane axes u (right) and v (up) as seen from outside.
  const Vec3 faces[6][3] = {{{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
                            {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                            {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}};
  for (const auto& f : faces) {
    const auto base = std::uint32_t(p.positions.size());
    const Vec3 n = f[0], u = f[1], v = f[2];
    const Vec3 c = n * h;
    p.positions.insert(p.positions.end(),
                       {c - u * h - v * h, c + u * h - v * h, c + u * h + v * h, c - u * h + v * h});
    p.normals.insert(p.normals.end(), 4, n);
    p.texcoords.insert(p.texcoords.end(), {{0, 1}, {1, 1}, {1, 0}, {0, 0}});
    p.indices.insert(p.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  return p;
}

PrimitiveData dense_grid(int n, int material) {
  PrimitiveData p;
  p.material = material;
  const int v = n + 1;
  p.positions.reserve(std::size_t(v) * std::size_t(v));
  for (int j = 0; j < v; ++j)
    for (int i = 0; i < v; ++i) {
      const float x = float(i) / float(n) - 0.5f, y = float(j) / float(n) - 0.5f;
      const float z = 0.05f * std::sin(x * 40.f) * std::cos(y * 40.f);
      p.positions.emplace_back(x, y, z);
      p.normals.push_back(Vec3(-2.f * std::cos(x * 40.f) * std::cos(y * 40.f),
                               2.f * std::sin(x * 40.f) * std::sin(y * 40.f), 1.f)
                              .normalized());
    }
  p.indices.reserve(std::size_t(n) * std::size_t(n) * 6);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto a = std::uint32_t(j * v + i), b = a + 1, c = a + std::uint32_t(v), d = c + 1;
      p.indices.insert(p.indices.end(), {a, b, d, a, d, c});
    }
  return p;
}

}  // namespace sylva::render::testing
