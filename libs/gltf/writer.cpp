// gltf::Scene -> tinygltf::Model -> bytes. Everything goes into one buffer in a fixed order
// (writer.h, "Layout"), so equal scenes give equal bytes. tinygltf serialises the JSON (keys in
// a fixed order) and frames the GLB; images are handed to it as buffer views with a mime type,
// which it writes as they are (it re-encodes only images given as decoded pixels).
//
// tinygltf comes from Debian's shared library (TinyGLTF::TinyGLTF), which already contains the
// implementation: no sylva translation unit defines TINYGLTF_IMPLEMENTATION.
#include "libs/gltf/writer.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "libs/gltf/draco_encode.h"

namespace sylva::gltf {
namespace {

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kUnlit = "KHR_materials_unlit";
constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";

tinygltf::Value to_value(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::boolean:
      return tinygltf::Value(j.get<bool>());
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned: {
      const double d = j.get<double>();
      if (d >= std::numeric_limits<int>::min() && d <= std::numeric_limits<int>::max())
        return tinygltf::Value(static_cast<int>(j.get<std::int64_t>()));
      return tinygltf::Value(d);
    }
    case nlohmann::json::value_t::number_float:
      return tinygltf::Value(j.get<double>());
    case nlohmann::json::value_t::string:
      return tinygltf::Value(j.get<std::string>());
    case nlohmann::json::value_t::array: {
      tinygltf::Value::Array a;
      for (const auto& e : j) a.push_back(to_value(e));
      return tinygltf::Value(std::move(a));
    }
    case nlohmann::json::value_t::object: {
      tinygltf::Value::Object o;
      for (auto it = j.begin(); it != j.end(); ++it) o.emplace(it.key(), to_value(it.value()));
      return tinygltf::Value(std::move(o));
    }
    default:
      return tinygltf::Value();
  }
}

class ModelBuilder {
 public:
  ModelBuilder(const Scene& scene, const WriteOptions& options) : s_(scene), o_(options) {}

  tinygltf::Model build() {
    m_.asset.version = "2.0";
    m_.asset.generator = s_.generator;
    if (!s_.extras.is_null()) m_.asset.extras = to_value(s_.extras);
    m_.buffers.emplace_back();
    for (const Material& mat : s_.materials) m_.materials.push_back(material(mat));
    for (const Mesh& mesh : s_.meshes) m_.meshes.push_back(this->mesh(mesh));
    for (const Node& n : s_.nodes) m_.nodes.push_back(node(n));
    tinygltf::Scene scene;
    scene.nodes = s_.roots;
    m_.scenes.push_back(scene);
    m_.defaultScene = 0;
    for (const Image& im : s_.images) {
      tinygltf::Image out;
      out.name = im.name;
      out.mimeType = im.mime_type;
      out.bufferView = add_view(im.bytes.data(), im.bytes.size(), 0);
      m_.images.push_back(std::move(out));
    }
    if (data_.empty()) {
      m_.buffers.clear();  // glTF forbids empty buffers
    } else {
      m_.buffers[0].data = std::move(data_);
    }
    for (const std::string& name : s_.extensions_required)
      if (used_.count(name)) required_.insert(name);
    m_.extensionsUsed.assign(used_.begin(), used_.end());
    m_.extensionsRequired.assign(required_.begin(), required_.end());
    return std::move(m_);
  }

 private:
  // Appends bytes at a 4-byte aligned offset; returns the buffer view index.
  int add_view(const void* bytes, std::size_t size, int target) {
    while (data_.size() % 4 != 0) data_.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = data_.size();
    v.byteLength = size;
    v.target = target;
    const auto* b = static_cast<const unsigned char*>(bytes);
    data_.insert(data_.end(), b, b + size);
    m_.bufferViews.push_back(v);
    return static_cast<int>(m_.bufferViews.size() - 1);
  }

  static int type_for(int components) {
    switch (components) {
      case 1: return TINYGLTF_TYPE_SCALAR;
      case 2: return TINYGLTF_TYPE_VEC2;
      case 3: return TINYGLTF_TYPE_VEC3;
      default: return TINYGLTF_TYPE_VEC4;
    }
  }

  // A FLOAT accessor; with `view` < 0 it has no buffer view (Draco).
  int float_accessor(const std::vector<float>& values, int components, std::size_t count, int view, bool min_max) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = type_for(components);
    a.count = count;
    if (min_max) {
      a.minValues.assign(static_cast<std::size_t>(components), std::numeric_limits<double>::infinity());
      a.maxValues.assign(static_cast<std::size_t>(components), -std::numeric_limits<double>::infinity());
      for (std::size_t i = 0; i < values.size(); ++i) {
        const std::size_t c = i % static_cast<std::size_t>(components);
        a.minValues[c] = std::min<double>(a.minValues[c], values[i]);
        a.maxValues[c] = std::max<double>(a.maxValues[c], values[i]);
      }
    }
    m_.accessors.push_back(a);
    return static_cast<int>(m_.accessors.size() - 1);
  }

  int float_attribute(const std::vector<float>& values, int components, bool min_max, int target) {
    const int view = add_view(values.data(), values.size() * sizeof(float), target);
    return float_accessor(values, components, values.size() / static_cast<std::size_t>(components), view, min_max);
  }

  static bool short_indices(std::size_t vertex_count) { return vertex_count <= 0xFFFF; }

  int index_accessor(const std::vector<std::uint32_t>& indices, std::size_t vertex_count) {
    tinygltf::Accessor a;
    a.type = TINYGLTF_TYPE_SCALAR;
    a.count = indices.size();
    if (short_indices(vertex_count)) {
      std::vector<std::uint16_t> narrow(indices.begin(), indices.end());
      a.bufferView = add_view(narrow.data(), narrow.size() * 2, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
      a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    } else {
      a.bufferView = add_view(indices.data(), indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
      a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    }
    m_.accessors.push_back(a);
    return static_cast<int>(m_.accessors.size() - 1);
  }

  static std::vector<const CustomAttribute*> sorted_custom(const Primitive& p) {
    std::vector<const CustomAttribute*> v;
    for (const CustomAttribute& a : p.custom) v.push_back(&a);
    std::sort(v.begin(), v.end(), [](auto* a, auto* b) { return a->name < b->name; });
    return v;
  }

  tinygltf::Primitive plain_primitive(const Primitive& p) {
    tinygltf::Primitive out;
    const int t = TINYGLTF_TARGET_ARRAY_BUFFER;
    out.attributes["POSITION"] = float_attribute(p.positions, 3, true, t);
    if (!p.normals.empty()) out.attributes["NORMAL"] = float_attribute(p.normals, 3, false, t);
    if (!p.tangents.empty()) out.attributes["TANGENT"] = float_attribute(p.tangents, 4, false, t);
    if (!p.texcoords.empty()) out.attributes["TEXCOORD_0"] = float_attribute(p.texcoords, 2, false, t);
    if (!p.colors.empty()) out.attributes["COLOR_0"] = float_attribute(p.colors, 4, false, t);
    for (const CustomAttribute* a : sorted_custom(p)) out.attributes[a->name] = float_attribute(a->values, a->components, false, t);
    if (!p.indices.empty()) out.indices = index_accessor(p.indices, p.vertex_count());
    return out;
  }

  tinygltf::Primitive draco_primitive(const Primitive& p) {
    const detail::DracoEncoded enc = detail::encode_draco(p, o_.draco);
    tinygltf::Primitive out;
    tinygltf::Value::Object attributes;
    for (const auto& [name, id] : enc.attribute_ids) {
      int comps = 0;
      const std::vector<float>* values = nullptr;
      if (name == "POSITION") {
        comps = 3, values = &p.positions;
      } else if (name == "NORMAL") {
        comps = 3, values = &p.normals;
      } else if (name == "TANGENT") {
        comps = 4, values = &p.tangents;
      } else if (name == "TEXCOORD_0") {
        comps = 2, values = &p.texcoords;
      } else if (name == "COLOR_0") {
        comps = 4, values = &p.colors;
      } else {
        for (const CustomAttribute& a : p.custom)
          if (a.name == name) comps = a.components, values = &a.values;
      }
      // POSITION min/max are those of the input; the decoded values differ by at most the
      // quantisation error (writer.h).
      out.attributes[name] = float_accessor(*values, comps, enc.points, -1, name == "POSITION");
      attributes.emplace(name, tinygltf::Value(id));
    }
    tinygltf::Accessor idx;
    idx.type = TINYGLTF_TYPE_SCALAR;
    idx.count = enc.faces * 3;
    idx.componentType = short_indices(enc.points) ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                                  : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    m_.accessors.push_back(idx);
    out.indices = static_cast<int>(m_.accessors.size() - 1);
    tinygltf::Value::Object ext;
    ext.emplace("bufferView", tinygltf::Value(add_view(enc.bytes.data(), enc.bytes.size(), 0)));
    ext.emplace("attributes", tinygltf::Value(std::move(attributes)));
    out.extensions[kDraco] = tinygltf::Value(std::move(ext));
    used_.insert(kDraco);
    required_.insert(kDraco);
    return out;
  }

  tinygltf::Mesh mesh(const Mesh& in) {
    tinygltf::Mesh out;
    out.name = in.name;
    for (const Primitive& p : in.primitives) {
      tinygltf::Primitive gp = o_.draco.enabled && p.mode == PrimitiveMode::kTriangles ? draco_primitive(p)
                                                                                       : plain_primitive(p);
      gp.mode = static_cast<int>(p.mode);
      gp.material = p.material;
      if (!p.extras.is_null()) gp.extras = to_value(p.extras);
      out.primitives.push_back(std::move(gp));
    }
    if (!in.extras.is_null()) out.extras = to_value(in.extras);
    return out;
  }

  // Samplers and textures are shared: one per distinct (wrap_s, wrap_t) and (image, sampler).
  int texture(const TextureRef& t) {
    const std::pair<int, int> wrap{static_cast<int>(t.wrap_s), static_cast<int>(t.wrap_t)};
    auto [sit, new_sampler] = samplers_.emplace(wrap, static_cast<int>(m_.samplers.size()));
    if (new_sampler) {
      tinygltf::Sampler s;
      s.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
      s.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
      s.wrapS = wrap.first;
      s.wrapT = wrap.second;
      m_.samplers.push_back(s);
    }
    const std::pair<int, int> key{t.image, sit->second};
    auto [tit, new_texture] = textures_.emplace(key, static_cast<int>(m_.textures.size()));
    if (new_texture) {
      tinygltf::Texture tex;
      tex.source = t.image;
      tex.sampler = sit->second;
      m_.textures.push_back(tex);
    }
    return tit->second;
  }

  tinygltf::Material material(const Material& in) {
    tinygltf::Material out;
    out.name = in.name;
    out.pbrMetallicRoughness.baseColorFactor.assign(in.base_color.begin(), in.base_color.end());
    out.pbrMetallicRoughness.metallicFactor = in.metallic;
    out.pbrMetallicRoughness.roughnessFactor = in.roughness;
    if (in.base_color_texture.image >= 0)
      out.pbrMetallicRoughness.baseColorTexture.index = texture(in.base_color_texture);
    switch (in.alpha_mode) {
      case AlphaMode::kOpaque: out.alphaMode = "OPAQUE"; break;
      case AlphaMode::kMask: out.alphaMode = "MASK"; break;
      case AlphaMode::kBlend: out.alphaMode = "BLEND"; break;
    }
    // tinygltf writes alphaCutoff whenever it differs from the default 0.5; glTF allows it with
    // MASK only.
    out.alphaCutoff = in.alpha_mode == AlphaMode::kMask ? in.alpha_cutoff : 0.5;
    out.doubleSided = in.double_sided;
    if (in.unlit) {
      out.extensions[kUnlit] = tinygltf::Value(tinygltf::Value::Object());
      used_.insert(kUnlit);
    }
    if (!in.extras.is_null()) out.extras = to_value(in.extras);
    return out;
  }

  tinygltf::Node node(const Node& in) {
    tinygltf::Node out;
    out.name = in.name;
    out.mesh = in.mesh;
    out.children = in.children;
    if (in.translation != std::array<double, 3>{0, 0, 0}) out.translation.assign(in.translation.begin(), in.translation.end());
    if (in.rotation != std::array<double, 4>{0, 0, 0, 1}) out.rotation.assign(in.rotation.begin(), in.rotation.end());
    if (in.scale != std::array<double, 3>{1, 1, 1}) out.scale.assign(in.scale.begin(), in.scale.end());
    if (!in.instances.empty()) {
      tinygltf::Value::Object attributes;
      auto add = [&](const char* name, const std::vector<float>& v, int comps) {
        if (!v.empty()) attributes.emplace(name, tinygltf::Value(float_attribute(v, comps, false, 0)));
      };
      add("TRANSLATION", in.instances.translations, 3);
      add("ROTATION", in.instances.rotations, 4);
      add("SCALE", in.instances.scales, 3);
      tinygltf::Value::Object ext;
      ext.emplace("attributes", tinygltf::Value(std::move(attributes)));
      out.extensions[kInstancing] = tinygltf::Value(std::move(ext));
      used_.insert(kInstancing);
      required_.insert(kInstancing);
    }
    if (in.extensions.is_object())
      for (auto it = in.extensions.begin(); it != in.extensions.end(); ++it) {
        out.extensions[it.key()] = to_value(it.value());
        used_.insert(it.key());
      }
    if (!in.extras.is_null()) out.extras = to_value(in.extras);
    return out;
  }

  const Scene& s_;
  const WriteOptions& o_;
  tinygltf::Model m_;
  std::vector<unsigned char> data_;
  std::set<std::string> used_, required_;
  std::map<std::pair<int, int>, int> samplers_, textures_;
};

}  // namespace

const char* extension(FileFormat format) { return format == FileFormat::kGlb ? ".glb" : ".gltf"; }

std::string encode(const Scene& scene, const WriteOptions& options) {
  const std::vector<std::string> problems = validate_scene(scene);
  if (!problems.empty()) {
    std::string msg = "invalid glTF scene: " + problems.front();
    if (problems.size() > 1) msg += " (and " + std::to_string(problems.size() - 1) + " more problems)";
    throw GltfError(msg);
  }
  tinygltf::Model model = ModelBuilder(scene, options).build();
  tinygltf::TinyGLTF writer;
  std::ostringstream out(std::ios::binary);
  const bool glb = options.format == FileFormat::kGlb;
  if (!writer.WriteGltfSceneToStream(&model, out, /*prettyPrint=*/!glb, /*writeBinary=*/glb))
    throw GltfError("tinygltf could not serialise the scene");
  return std::move(out).str();
}

void write_file(const Scene& scene, const std::filesystem::path& path, const WriteOptions& options) {
  const std::string bytes = encode(scene, options);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw GltfError(path.string() + ": cannot open for writing");
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  f.close();
  if (!f) throw GltfError(path.string() + ": write failed");
}

}  // namespace sylva::gltf
