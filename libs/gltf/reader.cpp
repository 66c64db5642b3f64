// glTF -> gltf::Scene through tinygltf (Debian's shared library holds its implementation, as for
// libs/render/gltf_scene.cpp). Images are kept as their encoded bytes: a loader callback stores
// them instead of decoding, so a PNG goes through `pack` byte for byte.
#include "libs/gltf/reader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "libs/gltf/tinygltf_files.h"

namespace sylva::gltf {

namespace {

nlohmann::json to_json(const tinygltf::Value& v) {
  switch (v.Type()) {
    case tinygltf::BOOL_TYPE:
      return v.Get<bool>();
    case tinygltf::INT_TYPE:
      return v.Get<int>();
    case tinygltf::REAL_TYPE:
      return v.Get<double>();
    case tinygltf::STRING_TYPE:
      return v.Get<std::string>();
    case tinygltf::ARRAY_TYPE: {
      nlohmann::json a = nlohmann::json::array();
      for (std::size_t i = 0; i < v.ArrayLen(); ++i) a.push_back(to_json(v.Get(int(i))));
      return a;
    }
    case tinygltf::OBJECT_TYPE: {
      nlohmann::json o = nlohmann::json::object();
      for (const std::string& k : v.Keys()) o[k] = to_json(v.Get(k));
      return o;
    }
    default:
      return nullptr;
  }
}

nlohmann::json extensions_json(const tinygltf::ExtensionMap& m) {
  if (m.empty()) return nullptr;
  nlohmann::json o = nlohmann::json::object();
  for (const auto& [k, v] : m) o[k] = to_json(v);
  return o;
}

// Keeps the encoded bytes (tinygltf calls this instead of decoding with stb).
bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

class SceneReader {
 public:
  SceneReader(const tinygltf::Model& m, std::string file) : m_(m), file_(std::move(file)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw ReadError(file_ + ": " + where + ": " + what);
  }

  Scene read() {
    Scene s;
    if (m_.scenes.size() > 1) fail("scenes", "more than one scene");
    for (const auto& name : m_.extensionsRequired)
      if (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression" ||
          name == "KHR_mesh_quantization")
        fail("extensionsRequired", name + " is not read (decompress first)");
    s.generator = m_.asset.generator.empty() ? "sylva" : m_.asset.generator;
    s.extras = m_.asset.extras.Type() == tinygltf::NULL_TYPE ? nlohmann::json() : to_json(m_.asset.extras);
    s.extensions_required = m_.extensionsRequired;
    for (std::size_t i = 0; i < m_.images.size(); ++i) s.images.push_back(image(i));
    for (std::size_t i = 0; i < m_.materials.size(); ++i) s.materials.push_back(material(i));
    for (std::size_t i = 0; i < m_.meshes.size(); ++i) s.meshes.push_back(mesh(i));
    for (std::size_t i = 0; i < m_.nodes.size(); ++i) s.nodes.push_back(node(i));
    if (!m_.scenes.empty()) s.roots = m_.scenes[0].nodes;
    return s;
  }

 private:
  Image image(std::size_t i) const {
    const tinygltf::Image& in = m_.images[i];
    const std::string where = "images[" + std::to_string(i) + "]";
    if (in.image.empty()) fail(where, "has no data");
    Image out;
    out.name = in.name.empty() ? in.uri : in.name;
    out.mime_type = in.mimeType;
    if (out.mime_type.empty()) {
      const std::string u = in.uri;
      const bool jpg = u.size() > 4 && (u.ends_with(".jpg") || u.ends_with(".jpeg"));
      out.mime_type = jpg ? "image/jpeg" : "image/png";
    }
    out.bytes.assign(in.image.begin(), in.image.end());
    return out;
  }

  TextureRef texture(int index, const std::string& where) const {
    TextureRef t;
    if (index < 0) return t;
    if (std::size_t(index) >= m_.textures.size())
      fail(where, "texture " + std::to_string(index) + " does not exist");
    const tinygltf::Texture& tex = m_.textures[std::size_t(index)];
    if (tex.source < 0 || std::size_t(tex.source) >= m_.images.size())
      fail(where, "texture has no valid image");
    t.image = tex.source;
    if (tex.sampler >= 0 && std::size_t(tex.sampler) < m_.samplers.size()) {
      t.wrap_s = static_cast<Wrap>(m_.samplers[std::size_t(tex.sampler)].wrapS);
      t.wrap_t = static_cast<Wrap>(m_.samplers[std::size_t(tex.sampler)].wrapT);
    }
    return t;
  }

  Material material(std::size_t i) const {
    const tinygltf::Material& in = m_.materials[i];
    const std::string where = "materials[" + std::to_string(i) + "]";
    Material out;
    out.name = in.name;
    for (std::size_t c = 0; c < 4 && c < in.pbrMetallicRoughness.baseColorFactor.size(); ++c)
      out.base_color[c] = static_cast<float>(in.pbrMetallicRoughness.baseColorFactor[c]);
    out.base_color_texture = texture(in.pbrMetallicRoughness.baseColorTexture.index, where);
    out.normal_texture = texture(in.normalTexture.index, where);
    out.metallic = static_cast<float>(in.pbrMetallicRoughness.metallicFactor);
    out.roughness = static_cast<float>(in.pbrMetallicRoughness.roughnessFactor);
    out.alpha_mode = in.alphaMode == "MASK"    ? AlphaMode::kMask
                     : in.alphaMode == "BLEND" ? AlphaMode::kBlend
                                               : AlphaMode::kOpaque;
    out.alpha_cutoff = static_cast<float>(in.alphaCutoff);
    out.double_sided = in.doubleSided;
    out.unlit = in.extensions.count("KHR_materials_unlit") > 0;
    if (in.extras.Type() != tinygltf::NULL_TYPE) out.extras = to_json(in.extras);
    return out;
  }

  // The accessor's elements as floats, `components` per element (normalised integers scaled).
  std::vector<float> floats(int index, int components, bool float_only, const std::string& where) const {
    if (index < 0 || std::size_t(index) >= m_.accessors.size()) fail(where, "accessor out of range");
    const tinygltf::Accessor& a = m_.accessors[std::size_t(index)];
    if (a.sparse.isSparse) fail(where, "sparse accessors are not read");
    const int n = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    if (n != components)
      fail(where, "expected " + std::to_string(components) + " components, got " + std::to_string(n));
    if (float_only && a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(where, "not FLOAT (quantised attributes are not read)");
    const std::uint8_t* base = element_base(a, where);
    const std::size_t stride = element_stride(a);
    std::vector<float> out(a.count * std::size_t(n));
    for (std::size_t e = 0; e < a.count; ++e)
      for (int c = 0; c < n; ++c)
        out[e * std::size_t(n) + std::size_t(c)] = component(base + e * stride, c, a);
    return out;
  }

  float component(const std::uint8_t* p, int c, const tinygltf::Accessor& a) const {
    switch (a.componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float v;
        std::memcpy(&v, p + 4 * c, 4);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return a.normalized ? p[c] / 255.f : p[c];
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p + 2 * c, 2);
        return a.normalized ? v / 65535.f : v;
      }
      default:
        fail("accessor", "component type " + std::to_string(a.componentType) + " is not read");
    }
  }

  std::size_t element_stride(const tinygltf::Accessor& a) const {
    const tinygltf::BufferView& v = m_.bufferViews[std::size_t(a.bufferView)];
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType)) *
                     tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    return v.byteStride ? v.byteStride : std::size_t(size);
  }

  const std::uint8_t* element_base(const tinygltf::Accessor& a, const std::string& where) const {
    if (a.bufferView < 0 || std::size_t(a.bufferView) >= m_.bufferViews.size())
      fail(where, "accessor has no buffer view");
    const tinygltf::BufferView& v = m_.bufferViews[std::size_t(a.bufferView)];
    if (v.buffer < 0 || std::size_t(v.buffer) >= m_.buffers.size()) fail(where, "buffer view has no buffer");
    const std::vector<unsigned char>& data = m_.buffers[std::size_t(v.buffer)].data;
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType)) *
                     tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    if (size <= 0) fail(where, "unknown accessor type");
    const std::size_t need = a.count == 0 ? 0 : (a.count - 1) * element_stride(a) + std::size_t(size);
    if (v.byteOffset + a.byteOffset + need > data.size() || a.byteOffset + need > v.byteLength)
      fail(where, "accessor reaches past its buffer");
    return data.data() + v.byteOffset + a.byteOffset;
  }

  std::vector<std::uint32_t> indices(int index, const std::string& where) const {
    if (index < 0 || std::size_t(index) >= m_.accessors.size()) fail(where, "accessor out of range");
    const tinygltf::Accessor& a = m_.accessors[std::size_t(index)];
    if (a.sparse.isSparse) fail(where, "sparse accessors are not read");
    if (a.type != TINYGLTF_TYPE_SCALAR) fail(where, "indices must be SCALAR");
    const std::uint8_t* base = element_base(a, where);
    const std::size_t stride = element_stride(a);
    std::vector<std::uint32_t> out(a.count);
    for (std::size_t e = 0; e < a.count; ++e) {
      const std::uint8_t* p = base + e * stride;
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          out[e] = *p;
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t v;
          std::memcpy(&v, p, 2);
          out[e] = v;
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
          std::memcpy(&out[e], p, 4);
          break;
        default:
          fail(where, "indices must be unsigned integers");
      }
    }
    return out;
  }

  Mesh mesh(std::size_t i) const {
    const tinygltf::Mesh& in = m_.meshes[i];
    Mesh out;
    out.name = in.name;
    if (in.extras.Type() != tinygltf::NULL_TYPE) out.extras = to_json(in.extras);
    for (std::size_t k = 0; k < in.primitives.size(); ++k) {
      const tinygltf::Primitive& p = in.primitives[k];
      const std::string where = "meshes[" + std::to_string(i) + "].primitives[" + std::to_string(k) + "]";
      if (!p.extensions.empty())
        fail(where, "primitive extensions (" + p.extensions.begin()->first + ") are not read");
      Primitive q;
      switch (p.mode) {
        case TINYGLTF_MODE_POINTS:
          q.mode = PrimitiveMode::kPoints;
          break;
        case TINYGLTF_MODE_LINE:
          q.mode = PrimitiveMode::kLines;
          break;
        case TINYGLTF_MODE_TRIANGLES:
          q.mode = PrimitiveMode::kTriangles;
          break;
        default:
          fail(where, "mode " + std::to_string(p.mode) + " is not read (strips, fans, loops)");
      }
      for (const auto& [name, acc] : p.attributes) {
        const std::string at = where + ".attributes." + name;
        if (name == "POSITION")
          q.positions = floats(acc, 3, true, at);
        else if (name == "NORMAL")
          q.normals = floats(acc, 3, true, at);
        else if (name == "TANGENT")
          q.tangents = floats(acc, 4, true, at);
        else if (name == "TEXCOORD_0")
          q.texcoords = floats(acc, 2, true, at);
        else if (name == "COLOR_0") {
          const int n = tinygltf::GetNumComponentsInType(
              static_cast<std::uint32_t>(m_.accessors.at(std::size_t(acc)).type));
          q.colors = floats(acc, n, false, at);
          if (n == 3) {
            std::vector<float> rgba;
            for (std::size_t v = 0; v + 2 < q.colors.size(); v += 3)
              rgba.insert(rgba.end(), {q.colors[v], q.colors[v + 1], q.colors[v + 2], 1.0f});
            q.colors = std::move(rgba);
          }
        } else if (!name.empty() && name[0] == '_') {
          const int n = tinygltf::GetNumComponentsInType(
              static_cast<std::uint32_t>(m_.accessors.at(std::size_t(acc)).type));
          q.custom.push_back({name, n, floats(acc, n, true, at)});
        } else {
          fail(at, "attribute is not read");
        }
      }
      std::sort(q.custom.begin(), q.custom.end(),
                [](const auto& a, const auto& b) { return a.name < b.name; });
      if (p.indices >= 0) q.indices = indices(p.indices, where + ".indices");
      q.material = p.material;
      if (p.extras.Type() != tinygltf::NULL_TYPE) q.extras = to_json(p.extras);
      out.primitives.push_back(std::move(q));
    }
    return out;
  }

  Node node(std::size_t i) const {
    const tinygltf::Node& in = m_.nodes[i];
    const std::string where = "nodes[" + std::to_string(i) + "]";
    if (!in.matrix.empty()) fail(where, "node matrices are not read");
    Node out;
    out.name = in.name;
    out.mesh = in.mesh;
    out.children = in.children;
    for (std::size_t c = 0; c < 3 && c < in.translation.size(); ++c) out.translation[c] = in.translation[c];
    for (std::size_t c = 0; c < 4 && c < in.rotation.size(); ++c) out.rotation[c] = in.rotation[c];
    for (std::size_t c = 0; c < 3 && c < in.scale.size(); ++c) out.scale[c] = in.scale[c];
    tinygltf::ExtensionMap ext = in.extensions;
    if (ext.count("EXT_mesh_gpu_instancing")) fail(where, "EXT_mesh_gpu_instancing is not read");
    out.extensions = extensions_json(ext);
    if (in.extras.Type() != tinygltf::NULL_TYPE) out.extras = to_json(in.extras);
    return out;
  }

  const tinygltf::Model& m_;
  std::string file_;
};

}  // namespace

Scene read_scene(const std::filesystem::path& path, const fileio::FileSource& files) {
  const std::string file = path.string();
  std::string bytes;
  try {
    bytes = files.read(path);
  } catch (const fileio::FileReadError& e) {
    throw ReadError(e.what());
  }
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) throw ReadError(file + ": larger than 4 GiB");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(keep_image_bytes, nullptr);
  loader.SetFsCallbacks(file_callbacks(files));
  tinygltf::Model model;
  std::string err, warn;
  const std::string base_dir = path.parent_path().string();
  const auto size = static_cast<unsigned int>(bytes.size());
  const bool ok =
      path.extension() == ".glb"
          ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                        reinterpret_cast<const unsigned char*>(bytes.data()), size, base_dir)
          : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, base_dir);
  if (!ok) {
    std::string msg = err.empty() ? "cannot be read" : err;
    while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
    throw ReadError(file + ": " + msg);
  }
  return SceneReader(model, file).read();
}

}  // namespace sylva::gltf
