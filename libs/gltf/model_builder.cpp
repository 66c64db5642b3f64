// The builder walks the scene once, in the order of writer.h's "Layout"; attribute bytes go
// through AccessorWriter (views, accessors) and AttributeQuantizer (KHR_mesh_quantization), so
// this file decides only what is written, not how the bytes are laid out. Materials no primitive
// uses and images no written material uses are pruned first, and every index is remapped.
#include "libs/gltf/model_builder.h"

#include <algorithm>
#include <array>
#include <limits>
#include <set>

#include "libs/gltf/accessor_writer.h"
#include "libs/gltf/draco_encode.h"
#include "libs/gltf/quantized_attributes.h"

namespace sylva::gltf::detail {
namespace {

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kUnlit = "KHR_materials_unlit";
constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";
constexpr const char* kQuantization = "KHR_mesh_quantization";
constexpr const char* kTextureTransform = "KHR_texture_transform";

// v rotated by the unit quaternion r (xyzw).
std::array<double, 3> rotate(const std::array<double, 4>& r, const std::array<double, 3>& v) {
  const std::array<double, 3> u{r[0], r[1], r[2]};
  auto cross = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                 a[0] * b[1] - a[1] * b[0]};
  };
  const std::array<double, 3> c1 = cross(u, v), c2 = cross(u, c1);
  return {v[0] + 2 * (r[3] * c1[0] + c2[0]), v[1] + 2 * (r[3] * c1[1] + c2[1]),
          v[2] + 2 * (r[3] * c1[2] + c2[2])};
}

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
  ModelBuilder(const Scene& scene, const WriteOptions& options)
      : s_(scene),
        o_(options),
        external_(options.format == FileFormat::kGltfExternal),
        views_(m_, external_ ? std::max<std::size_t>(1, scene.buffer_uris.size()) : 1),
        quantizer_(views_, options.quantize, options.meshopt) {}

  BuiltModel build() {
    m_.asset.version = "2.0";
    m_.asset.generator = s_.generator;
    if (!s_.extras.is_null()) m_.asset.extras = to_value(s_.extras);
    prune();
    plan_grids();
    for (int i : used_materials_)
      m_.materials.push_back(material(s_.materials[std::size_t(i)], std::size_t(i)));
    for (std::size_t i = 0; i < s_.meshes.size(); ++i) {
      const Mesh& mesh = s_.meshes[i];
      views_.set_buffer(external_ ? mesh.buffer : 0);
      mesh_index_ = i;
      m_.meshes.push_back(this->mesh(mesh));
    }
    for (std::size_t i = 0; i < s_.nodes.size(); ++i) {
      const Node& n = s_.nodes[i];
      views_.set_buffer(external_ && n.mesh >= 0 ? s_.meshes[std::size_t(n.mesh)].buffer : 0);
      m_.nodes.push_back(node(n, i));
    }
    tinygltf::Scene scene;
    scene.nodes = s_.roots;
    m_.scenes.push_back(scene);
    m_.defaultScene = 0;
    views_.set_buffer(0);
    add_images();
    if (!external_) {
      if (!views_.data(0).empty()) {  // glTF forbids empty buffers
        m_.buffers.emplace_back();
        m_.buffers[0].data = std::move(views_.data(0));
      }
    } else {
      add_external_buffers();
    }
    if (quantizer_.wrote_integers()) mark_required(kQuantization);
    for (const std::string& name : s_.extensions_required)
      if (used_.count(name)) required_.insert(name);
    m_.extensionsUsed.assign(used_.begin(), used_.end());
    m_.extensionsRequired.assign(required_.begin(), required_.end());
    return {std::move(m_), views_.filters(), std::move(resources_), std::move(buffer_sizes_)};
  }

 private:
  void mark_required(const char* extension) {
    used_.insert(extension);
    required_.insert(extension);
  }

  // The used images, in order: in the current buffer, or (kGltfExternal, with a uri) a file.
  void add_images() {
    for (int i : used_images_) {
      const Image& im = s_.images[std::size_t(i)];
      tinygltf::Image out;
      out.name = im.name;
      out.mimeType = im.mime_type;
      if (external_ && !im.uri.empty()) {
        out.uri = im.uri;
        resources_.push_back({im.uri, im.bytes});
      } else {
        out.bufferView = views_.add_view(im.bytes.data(), im.bytes.size(), 0);
      }
      m_.images.push_back(std::move(out));
    }
  }

  // kGltfExternal: every buffer becomes a resource named by Scene::buffer_uris, placed before
  // the image files.
  void add_external_buffers() {
    for (std::size_t b = 0; b < views_.buffer_count(); ++b) {
      std::vector<unsigned char>& data = views_.data(b);
      const std::string uri = s_.buffer_uris.empty() ? std::string() : s_.buffer_uris[b];
      if (data.empty())
        throw GltfError("invalid glTF scene: buffer_uris[" + std::to_string(b) + "] ('" + uri +
                        "') holds no data");
      if (uri.empty()) throw GltfError("invalid glTF scene: an external .gltf needs buffer_uris");
      m_.buffers.emplace_back();
      m_.buffers.back().uri = uri;
      const std::size_t declared = b < s_.buffer_byte_lengths.size() ? s_.buffer_byte_lengths[b] : 0;
      if (declared != 0 && declared < data.size())
        throw GltfError("invalid glTF scene: buffer_byte_lengths[" + std::to_string(b) + "] is " +
                        std::to_string(declared) + ", less than the buffer's " + std::to_string(data.size()) +
                        " bytes");
      buffer_sizes_.push_back(declared != 0 ? declared : data.size());
      resources_.insert(resources_.begin() + std::ptrdiff_t(b), {uri, std::string(data.begin(), data.end())});
      std::vector<unsigned char>().swap(data);
    }
  }

  // Materials no primitive uses and images no written material uses are not written; the
  // indices of the rest are remapped (in their original order).
  void prune() {
    std::vector<char> mat_used(s_.materials.size(), 0), img_used(s_.images.size(), 0);
    for (const Mesh& m : s_.meshes)
      for (const Primitive& p : m.primitives)
        if (p.material >= 0) mat_used[std::size_t(p.material)] = 1;
    material_index_.assign(s_.materials.size(), -1);
    for (std::size_t i = 0; i < s_.materials.size(); ++i) {
      if (!mat_used[i]) continue;
      material_index_[i] = static_cast<int>(used_materials_.size());
      used_materials_.push_back(static_cast<int>(i));
      for (const int t : {s_.materials[i].base_color_texture.image, s_.materials[i].normal_texture.image})
        if (t >= 0) img_used[std::size_t(t)] = 1;
    }
    image_index_.assign(s_.images.size(), -1);
    for (std::size_t i = 0; i < s_.images.size(); ++i)
      if (img_used[i]) {
        image_index_[i] = static_cast<int>(used_images_.size());
        used_images_.push_back(static_cast<int>(i));
      }
  }

  // Each node's parent (for undoing a quantised parent's grid), and the quantisation plan when
  // the file is quantised (QuantizeOptions: ignored with Draco).
  void plan_grids() {
    parent_.assign(s_.nodes.size(), -1);
    for (std::size_t n = 0; n < s_.nodes.size(); ++n)
      for (int c : s_.nodes[n].children)
        if (c >= 0 && std::size_t(c) < s_.nodes.size()) parent_[std::size_t(c)] = static_cast<int>(n);
    quantize_ = o_.quantize.enabled && !o_.draco.enabled;
    if (!quantize_) {
      grids_.assign(s_.meshes.size(), PositionGrid{});
      return;
    }
    QuantizePlan plan = plan_quantization(s_, o_.quantize);
    grids_ = std::move(plan.grids);
    uv_grid_ = std::move(plan.uv_grid);
  }

  static std::vector<const CustomAttribute*> sorted_custom(const Primitive& p) {
    std::vector<const CustomAttribute*> v;
    for (const CustomAttribute& a : p.custom) v.push_back(&a);
    std::sort(v.begin(), v.end(), [](auto* a, auto* b) { return a->name < b->name; });
    return v;
  }

  // Tangents serve normal maps only (TEAM decision): without one they are dead weight (a quarter
  // of a mesh's vertex bytes).
  bool writes_tangents(const Primitive& p) const {
    return !p.tangents.empty() && p.material >= 0 &&
           s_.materials[std::size_t(p.material)].normal_texture.image >= 0;
  }

  tinygltf::Primitive plain_primitive(const Primitive& p) {
    tinygltf::Primitive out;
    const int t = TINYGLTF_TARGET_ARRAY_BUFFER;
    const PositionGrid& grid = grids_[mesh_index_];
    const double float_error =
        quantize_ && o_.meshopt && mesh_index_ < o_.quantize.float_position_error.size()
            ? o_.quantize.float_position_error[mesh_index_]
            : 0.0;
    out.attributes["POSITION"] = grid.bits > 0 ? quantizer_.grid_positions(p.positions, grid)
                                 : float_error > 0
                                     ? quantizer_.exponential_positions(p.positions, float_error)
                                     : views_.float_attribute(p.positions, 3, true, t);
    if (!p.normals.empty())
      out.attributes["NORMAL"] =
          quantize_ ? quantizer_.normals(p.normals) : views_.float_attribute(p.normals, 3, false, t);
    if (writes_tangents(p)) out.attributes["TANGENT"] = views_.float_attribute(p.tangents, 4, false, t);
    if (!p.texcoords.empty())
      out.attributes["TEXCOORD_0"] = quantize_ && p.material >= 0 && uv_grid_[std::size_t(p.material)]
                                         ? quantizer_.grid_texcoords(p.texcoords)
                                     : quantize_ && in_unit_range(p.texcoords)
                                         ? quantizer_.unorm(p.texcoords, 2, o_.quantize.texcoord_bits, false)
                                         : views_.float_attribute(p.texcoords, 2, false, t);
    if (!p.colors.empty())
      out.attributes["COLOR_0"] = quantize_ ? quantizer_.unorm(p.colors, 4, o_.quantize.color_bits, true)
                                            : views_.float_attribute(p.colors, 4, false, t);
    for (const CustomAttribute* a : sorted_custom(p))
      out.attributes[a->name] = views_.float_attribute(a->values, a->components, false, t);
    if (!p.indices.empty()) out.indices = views_.index_accessor(p.indices, p.vertex_count());
    return out;
  }

  tinygltf::Primitive draco_primitive(const Primitive& p) {
    const detail::DracoEncoded enc = detail::encode_draco(p, o_.draco, writes_tangents(p));
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
      out.attributes[name] = views_.float_accessor(*values, comps, enc.points, -1, name == "POSITION");
      attributes.emplace(name, tinygltf::Value(id));
    }
    out.indices = views_.add_accessor_without_view(TINYGLTF_TYPE_SCALAR, enc.faces * 3,
                                                   AccessorWriter::short_indices(enc.points)
                                                       ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                                       : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
    tinygltf::Value::Object ext;
    ext.emplace("bufferView", tinygltf::Value(views_.add_view(enc.bytes.data(), enc.bytes.size(), 0)));
    ext.emplace("attributes", tinygltf::Value(std::move(attributes)));
    out.extensions[kDraco] = tinygltf::Value(std::move(ext));
    mark_required(kDraco);
    return out;
  }

  tinygltf::Mesh mesh(const Mesh& in) {
    tinygltf::Mesh out;
    out.name = in.name;
    const int mesh_buffer = views_.buffer();
    for (const Primitive& p : in.primitives) {
      views_.set_buffer(external_ && p.buffer >= 0 ? p.buffer : mesh_buffer);
      tinygltf::Primitive gp =
          o_.draco.enabled && p.mode == PrimitiveMode::kTriangles ? draco_primitive(p) : plain_primitive(p);
      gp.mode = static_cast<int>(p.mode);
      gp.material = p.material >= 0 ? material_index_[std::size_t(p.material)] : -1;
      if (!p.extras.is_null()) gp.extras = to_value(p.extras);
      out.primitives.push_back(std::move(gp));
    }
    views_.set_buffer(mesh_buffer);
    if (!in.extras.is_null()) out.extras = to_value(in.extras);
    return out;
  }

  // Samplers and textures are shared: one per distinct (wrap_s, wrap_t) and (image, sampler).
  int texture(const TextureRef& t) {
    const int image = image_index_[std::size_t(t.image)];
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
    const std::pair<int, int> key{image, sit->second};
    auto [tit, new_texture] = textures_.emplace(key, static_cast<int>(m_.textures.size()));
    if (new_texture) {
      tinygltf::Texture tex;
      tex.source = image;
      tex.sampler = sit->second;
      m_.textures.push_back(tex);
    }
    return tit->second;
  }

  tinygltf::Material material(const Material& in, std::size_t index) {
    tinygltf::Material out;
    out.name = in.name;
    out.pbrMetallicRoughness.baseColorFactor.assign(in.base_color.begin(), in.base_color.end());
    out.pbrMetallicRoughness.metallicFactor = in.metallic;
    out.pbrMetallicRoughness.roughnessFactor = in.roughness;
    if (in.base_color_texture.image >= 0)
      out.pbrMetallicRoughness.baseColorTexture.index = texture(in.base_color_texture);
    if (in.normal_texture.image >= 0) out.normalTexture.index = texture(in.normal_texture);
    if (index < uv_grid_.size() && uv_grid_[index]) {
      // The material's uvs are integers k / 65535 on the texcoord grid: scale them back to
      // k / (2^B - 1) (QuantizeOptions::texcoord_bits).
      const double scale = 65535.0 / double((1u << o_.quantize.texcoord_bits) - 1);
      tinygltf::Value::Object t;
      t.emplace("scale",
                tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(scale), tinygltf::Value(scale)}));
      const tinygltf::Value v(std::move(t));
      if (in.base_color_texture.image >= 0)
        out.pbrMetallicRoughness.baseColorTexture.extensions[kTextureTransform] = v;
      if (in.normal_texture.image >= 0) out.normalTexture.extensions[kTextureTransform] = v;
      mark_required(kTextureTransform);
    }
    switch (in.alpha_mode) {
      case AlphaMode::kOpaque:
        out.alphaMode = "OPAQUE";
        break;
      case AlphaMode::kMask:
        out.alphaMode = "MASK";
        break;
      case AlphaMode::kBlend:
        out.alphaMode = "BLEND";
        break;
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

  // A node drawing a quantised mesh M gets M's dequantisation D = T(lo) S(step) after its own
  // transform (L' = L D); a child of such a node gets D's inverse before its own (C' = D^-1 C),
  // so world transforms of everything else are unchanged. Both stay TRS: the scale is uniform.
  tinygltf::Node node(const Node& in, std::size_t index) {
    tinygltf::Node out;
    out.name = in.name;
    out.mesh = in.mesh;
    out.children = in.children;
    std::array<double, 3> t = in.translation, s = in.scale;
    if (in.mesh >= 0 && grids_[std::size_t(in.mesh)].bits > 0) {
      const PositionGrid& g = grids_[std::size_t(in.mesh)];
      const std::array<double, 3> o = rotate(in.rotation, {s[0] * g.lo[0], s[1] * g.lo[1], s[2] * g.lo[2]});
      for (std::size_t c = 0; c < 3; ++c) t[c] += o[c], s[c] *= g.step;
    }
    const int parent = parent_[index];
    const int parent_mesh = parent >= 0 ? s_.nodes[std::size_t(parent)].mesh : -1;
    if (parent_mesh >= 0 && grids_[std::size_t(parent_mesh)].bits > 0) {
      const PositionGrid& g = grids_[std::size_t(parent_mesh)];
      for (std::size_t c = 0; c < 3; ++c) t[c] = (t[c] - g.lo[c]) / g.step, s[c] /= g.step;
    }
    if (t != std::array<double, 3>{0, 0, 0}) out.translation.assign(t.begin(), t.end());
    if (in.rotation != std::array<double, 4>{0, 0, 0, 1})
      out.rotation.assign(in.rotation.begin(), in.rotation.end());
    if (s != std::array<double, 3>{1, 1, 1}) out.scale.assign(s.begin(), s.end());
    if (!in.instances.empty()) {
      tinygltf::Value::Object attributes;
      auto add = [&](const char* name, const std::vector<float>& v, int comps) {
        if (!v.empty()) attributes.emplace(name, tinygltf::Value(views_.float_attribute(v, comps, false, 0)));
      };
      add("TRANSLATION", in.instances.translations, 3);
      add("ROTATION", in.instances.rotations, 4);
      add("SCALE", in.instances.scales, 3);
      tinygltf::Value::Object ext;
      ext.emplace("attributes", tinygltf::Value(std::move(attributes)));
      out.extensions[kInstancing] = tinygltf::Value(std::move(ext));
      mark_required(kInstancing);
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
  bool external_ = false;
  AccessorWriter views_;
  AttributeQuantizer quantizer_;
  bool quantize_ = false;
  std::size_t mesh_index_ = 0;       // the mesh being built
  std::vector<PositionGrid> grids_;  // per mesh
  std::vector<int> parent_;          // per node, -1 = root
  std::vector<char> uv_grid_;        // per material: its uvs on the texcoord grid (KHR_texture_transform)
  std::vector<int> used_materials_, used_images_, material_index_, image_index_;
  std::vector<EncodedFile> resources_;
  std::vector<std::size_t> buffer_sizes_;
  std::set<std::string> used_, required_;
  std::map<std::pair<int, int>, int> samplers_, textures_;
};

}  // namespace

BuiltModel build_model(const Scene& scene, const WriteOptions& options) {
  ModelBuilder builder(scene, options);
  return builder.build();
}

}  // namespace sylva::gltf::detail
