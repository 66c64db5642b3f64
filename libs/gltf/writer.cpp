// gltf::Scene -> tinygltf::Model -> bytes. Everything goes into one buffer (external .gltf: one
// buffer per Scene::buffer_uris entry) in a fixed order (writer.h, "Layout"), so equal scenes
// give equal bytes. tinygltf serialises the JSON (keys in
// a fixed order) and frames the GLB; images are handed to it as buffer views with a mime type,
// which it writes as they are (it re-encodes only images given as decoded pixels).
//
// tinygltf comes from Debian's shared library (TinyGLTF::TinyGLTF), which already contains the
// implementation: no sylva translation unit defines TINYGLTF_IMPLEMENTATION.
#include "libs/gltf/writer.h"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "libs/gltf/draco_encode.h"
#include "libs/gltf/meshopt_encode.h"

namespace sylva::gltf {
namespace {

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kUnlit = "KHR_materials_unlit";
constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";
constexpr const char* kQuantization = "KHR_mesh_quantization";
constexpr const char* kTextureTransform = "KHR_texture_transform";

// v in [0, 1] on the grid of `bits`-bit steps inside a `to`-bit normalized integer: k * 2^(to -
// bits) with k = meshopt_quantizeUnorm(v * (2^to - 1) / (2^to - 2^(to - bits)), bits), so the low
// bits are zero (the codecs compress them away) and the integer decodes to within half a
// `bits`-bit step of v (within one step for v in the top step, which clamps to the largest k).
unsigned on_grid(float v, int bits, int to) {
  if (bits >= to) return unsigned(meshopt_quantizeUnorm(v, to));
  const double full = double((1u << to) - 1), top = double((1u << to) - (1u << (to - bits)));
  return unsigned(meshopt_quantizeUnorm(float(double(v) * full / top), bits)) << (to - bits);
}

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
  // A mesh's position grid (QuantizeOptions::position_bits); bits 0 = FLOAT positions.
  struct Grid {
    int bits = 0;
    std::array<double, 3> lo{0, 0, 0};
    double extent = 0, step = 1;
  };

 public:
  ModelBuilder(const Scene& scene, const WriteOptions& options) : s_(scene), o_(options) {}

  // The model; with kGltfExternal its buffers carry no data (external_data() has it) and images
  // with a uri carry neither a buffer view nor bytes.
  tinygltf::Model build() {
    m_.asset.version = "2.0";
    m_.asset.generator = s_.generator;
    if (!s_.extras.is_null()) m_.asset.extras = to_value(s_.extras);
    external_ = o_.format == FileFormat::kGltfExternal;
    data_.resize(external_ ? std::max<std::size_t>(1, s_.buffer_uris.size()) : 1);
    prune();
    plan_grids();
    for (int i : used_materials_)
      m_.materials.push_back(material(s_.materials[std::size_t(i)], std::size_t(i)));
    for (std::size_t i = 0; i < s_.meshes.size(); ++i) {
      const Mesh& mesh = s_.meshes[i];
      buffer_ = external_ ? mesh.buffer : 0;
      mesh_index_ = i;
      m_.meshes.push_back(this->mesh(mesh));
    }
    for (std::size_t i = 0; i < s_.nodes.size(); ++i) {
      const Node& n = s_.nodes[i];
      buffer_ = external_ && n.mesh >= 0 ? s_.meshes[std::size_t(n.mesh)].buffer : 0;
      m_.nodes.push_back(node(n, i));
    }
    tinygltf::Scene scene;
    scene.nodes = s_.roots;
    m_.scenes.push_back(scene);
    m_.defaultScene = 0;
    buffer_ = 0;
    for (int i : used_images_) {
      const Image& im = s_.images[std::size_t(i)];
      tinygltf::Image out;
      out.name = im.name;
      out.mimeType = im.mime_type;
      if (external_ && !im.uri.empty()) {
        out.uri = im.uri;
        resources_.push_back({im.uri, im.bytes});
      } else {
        out.bufferView = add_view(im.bytes.data(), im.bytes.size(), 0);
      }
      m_.images.push_back(std::move(out));
    }
    if (!external_) {
      if (!data_[0].empty()) {  // glTF forbids empty buffers
        m_.buffers.emplace_back();
        m_.buffers[0].data = std::move(data_[0]);
      }
    } else {
      for (std::size_t b = 0; b < data_.size(); ++b) {
        const std::string uri = s_.buffer_uris.empty() ? std::string() : s_.buffer_uris[b];
        if (data_[b].empty())
          throw GltfError("invalid glTF scene: buffer_uris[" + std::to_string(b) + "] ('" + uri +
                          "') holds no data");
        if (uri.empty()) throw GltfError("invalid glTF scene: an external .gltf needs buffer_uris");
        m_.buffers.emplace_back();
        m_.buffers.back().uri = uri;
        const std::size_t declared = b < s_.buffer_byte_lengths.size() ? s_.buffer_byte_lengths[b] : 0;
        if (declared != 0 && declared < data_[b].size())
          throw GltfError("invalid glTF scene: buffer_byte_lengths[" + std::to_string(b) + "] is " +
                          std::to_string(declared) + ", less than the buffer's " +
                          std::to_string(data_[b].size()) + " bytes");
        buffer_sizes_.push_back(declared != 0 ? declared : data_[b].size());
        resources_.insert(resources_.begin() + std::ptrdiff_t(b),
                          {uri, std::string(data_[b].begin(), data_[b].end())});
        std::vector<unsigned char>().swap(data_[b]);
      }
    }
    for (const std::string& name : s_.extensions_required)
      if (used_.count(name)) required_.insert(name);
    m_.extensionsUsed.assign(used_.begin(), used_.end());
    m_.extensionsRequired.assign(required_.begin(), required_.end());
    return std::move(m_);
  }

  // kGltfExternal: (uri, bytes) of every buffer in order, then of every image file.
  std::vector<EncodedFile> take_resources() { return std::move(resources_); }
  // The meshopt filter of each view whose bytes are filtered (octahedral normals).
  const std::map<int, std::string>& view_filters() const { return filters_; }
  const std::vector<std::size_t>& buffer_sizes() const { return buffer_sizes_; }

 private:
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

  // Quantisation: checks the options and chooses each mesh's position grid (QuantizeOptions).
  void plan_grids() {
    grids_.assign(s_.meshes.size(), Grid{});
    parent_.assign(s_.nodes.size(), -1);
    for (std::size_t n = 0; n < s_.nodes.size(); ++n)
      for (int c : s_.nodes[n].children)
        if (c >= 0 && std::size_t(c) < s_.nodes.size()) parent_[std::size_t(c)] = static_cast<int>(n);
    quantize_ = o_.quantize.enabled && !o_.draco.enabled;
    if (!quantize_) return;
    const QuantizeOptions& q = o_.quantize;
    for (const auto& [name, bits] : {std::pair<const char*, int>{"normal_bits", q.normal_bits},
                                     {"texcoord_bits", q.texcoord_bits},
                                     {"color_bits", q.color_bits}})
      if (bits < 1 || bits > 16)
        throw GltfError(std::string("quantize.") + name + " is " + std::to_string(bits) + ", expected 1..16");
    // Materials whose textures can take the uv grid through KHR_texture_transform: textured, and
    // every primitive drawn with them has uvs in [0, 1].
    uv_grid_.assign(s_.materials.size(), 0);
    for (std::size_t i = 0; i < s_.materials.size(); ++i)
      uv_grid_[i] =
          s_.materials[i].base_color_texture.image >= 0 || s_.materials[i].normal_texture.image >= 0;
    for (const Mesh& mesh : s_.meshes)
      for (const Primitive& p : mesh.primitives)
        if (p.material >= 0 && !p.texcoords.empty() && !in_unit_range(p.texcoords))
          uv_grid_[std::size_t(p.material)] = 0;
    std::vector<char> instanced(s_.meshes.size(), 0);
    for (const Node& n : s_.nodes)
      if (n.mesh >= 0 && !n.instances.empty()) instanced[std::size_t(n.mesh)] = 1;
    for (std::size_t m = 0; m < s_.meshes.size() && m < q.position_bits.size(); ++m) {
      const int bits = q.position_bits[m];
      if (bits < 0 || bits > 16)
        throw GltfError("quantize.position_bits[" + std::to_string(m) + "] is " + std::to_string(bits) +
                        ", expected 0..16");
      if (bits == 0 || instanced[m]) continue;
      Grid g;
      g.bits = bits;
      std::array<double, 3> hi{};
      g.lo.fill(std::numeric_limits<double>::infinity());
      hi.fill(-std::numeric_limits<double>::infinity());
      for (const Primitive& p : s_.meshes[m].primitives)
        for (std::size_t i = 0; i < p.positions.size(); ++i) {
          g.lo[i % 3] = std::min<double>(g.lo[i % 3], p.positions[i]);
          hi[i % 3] = std::max<double>(hi[i % 3], p.positions[i]);
        }
      for (int c = 0; c < 3; ++c) g.extent = std::max(g.extent, hi[std::size_t(c)] - g.lo[std::size_t(c)]);
      g.step = g.extent > 0 ? g.extent / double((1u << bits) - 1) : 1.0;
      grids_[m] = g;
    }
  }

  void mark_quantized() {
    used_.insert(kQuantization);
    required_.insert(kQuantization);
  }

  // An integer vertex attribute: `bytes` holds count elements of `stride` bytes.
  int integer_attribute(const void* bytes, std::size_t count, std::size_t stride, int component_type,
                        int components, bool normalized) {
    const int view = add_view(bytes, count * stride, TINYGLTF_TARGET_ARRAY_BUFFER);
    m_.bufferViews[std::size_t(view)].byteStride = stride;
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = component_type;
    a.type = type_for(components);
    a.count = count;
    a.normalized = normalized;
    m_.accessors.push_back(a);
    mark_quantized();
    return static_cast<int>(m_.accessors.size() - 1);
  }

  // POSITION on the mesh's grid: UNSIGNED_SHORT xyz + 2 padding bytes, with integer min/max.
  int quantized_positions(const std::vector<float>& v, const Grid& g) {
    const std::size_t n = v.size() / 3;
    std::vector<std::uint16_t> q(n * 4, 0);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        const double t = g.extent > 0 ? (double(v[i * 3 + c]) - g.lo[c]) / g.extent : 0.0;
        q[i * 4 + c] = static_cast<std::uint16_t>(meshopt_quantizeUnorm(float(t), g.bits));
      }
    const int acc = integer_attribute(q.data(), n, 8, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, 3, false);
    tinygltf::Accessor& a = m_.accessors[std::size_t(acc)];
    a.minValues.assign(3, std::numeric_limits<double>::infinity());
    a.maxValues.assign(3, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < 3; ++c) {
        a.minValues[c] = std::min<double>(a.minValues[c], q[i * 4 + c]);
        a.maxValues[c] = std::max<double>(a.maxValues[c], q[i * 4 + c]);
      }
    return acc;
  }

  // FLOAT POSITION through the EXPONENTIAL filter with the fewest mantissa bits that keep every
  // vertex within max_error (QuantizeOptions::float_position_error); min/max of what decodes.
  int exponential_positions(const std::vector<float>& v, double max_error) {
    const std::size_t n = v.size() / 3;
    std::vector<unsigned char> encoded(n * 12);
    auto decodes_within = [&](int bits) {
      meshopt_encodeFilterExp(encoded.data(), n, 12, bits, v.data());
      std::vector<unsigned char> decoded = encoded;
      meshopt_decodeFilterExp(decoded.data(), n, 12);
      const float* d = reinterpret_cast<const float*>(decoded.data());
      for (std::size_t i = 0; i < n; ++i) {
        double e2 = 0;
        for (std::size_t c = 0; c < 3; ++c)
          e2 += (double(d[i * 3 + c]) - v[i * 3 + c]) * (double(d[i * 3 + c]) - v[i * 3 + c]);
        if (std::sqrt(e2) > max_error) return false;
      }
      return true;
    };
    int lo = 1, hi = 24;  // 24 bits keep a float's whole mantissa
    while (lo < hi) {
      const int mid = (lo + hi) / 2;
      if (decodes_within(mid)) {
        hi = mid;
      } else {
        lo = mid + 1;
      }
    }
    meshopt_encodeFilterExp(encoded.data(), n, 12, lo, v.data());
    std::vector<float> decoded(n * 3);
    std::memcpy(decoded.data(), encoded.data(), encoded.size());
    meshopt_decodeFilterExp(decoded.data(), n, 12);
    const int view = add_view(encoded.data(), encoded.size(), TINYGLTF_TARGET_ARRAY_BUFFER);
    m_.bufferViews[std::size_t(view)].byteStride = 12;
    filters_[view] = "EXPONENTIAL";
    return float_accessor(decoded, 3, n, view, true);
  }

  // NORMAL: octahedral through meshopt's filter when the file is meshopt-compressed, else
  // per-component snorm; BYTE or SHORT normalized VEC3 padded to 4 components.
  int quantized_normals(const std::vector<float>& v) {
    const int bits = o_.quantize.normal_bits;
    const bool wide = bits > 8;
    const std::size_t n = v.size() / 3, stride = wide ? 8 : 4;
    std::vector<unsigned char> out(n * stride, 0);
    if (o_.meshopt) {
      std::vector<float> v4(n * 4, 0.f);
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < 3; ++c) v4[i * 4 + c] = v[i * 3 + c];
      meshopt_encodeFilterOct(out.data(), n, stride, bits, v4.data());
    } else {
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < 3; ++c) {
          if (wide) {
            const auto k = static_cast<std::int16_t>(meshopt_quantizeSnorm(v[i * 3 + c], 16));
            std::memcpy(out.data() + i * 8 + c * 2, &k, 2);
          } else {
            out[i * 4 + c] =
                static_cast<unsigned char>(static_cast<std::int8_t>(meshopt_quantizeSnorm(v[i * 3 + c], 8)));
          }
        }
    }
    const int acc = integer_attribute(
        out.data(), n, stride, wide ? TINYGLTF_COMPONENT_TYPE_SHORT : TINYGLTF_COMPONENT_TYPE_BYTE, 3, true);
    if (o_.meshopt) filters_[m_.accessors[std::size_t(acc)].bufferView] = "OCTAHEDRAL";
    return acc;
  }

  // TEXCOORD_0 of a material with a uv grid: UNSIGNED_SHORT normalized k = meshopt_quantizeUnorm(uv,
  // B), which the material's KHR_texture_transform scales from k / 65535 to k / (2^B - 1).
  int grid_texcoords(const std::vector<float>& v) {
    const int bits = o_.quantize.texcoord_bits;
    std::vector<std::uint16_t> q(v.size());
    for (std::size_t i = 0; i < v.size(); ++i)
      q[i] = static_cast<std::uint16_t>(meshopt_quantizeUnorm(v[i], bits));
    return integer_attribute(q.data(), v.size() / 2, 4, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, 2, true);
  }

  // Unsigned normalized values in [0, 1] (texcoords, colours): `bits` bits widened to 8 or 16.
  int quantized_unorm(const std::vector<float>& v, int components, int bits, bool allow_byte) {
    const std::size_t n = v.size() / std::size_t(components);
    const bool byte = allow_byte && bits <= 8;
    const std::size_t stride = (std::size_t(components) * (byte ? 1 : 2) + 3) / 4 * 4;
    std::vector<unsigned char> out(n * stride, 0);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < std::size_t(components); ++c) {
        const unsigned k = on_grid(v[i * std::size_t(components) + c], bits, byte ? 8 : 16);
        if (byte) {
          out[i * stride + c] = static_cast<unsigned char>(k);
        } else {
          const auto k16 = static_cast<std::uint16_t>(k);
          std::memcpy(out.data() + i * stride + c * 2, &k16, 2);
        }
      }
    return integer_attribute(
        out.data(), n, stride,
        byte ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE : TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, components,
        true);
  }

  static bool in_unit_range(const std::vector<float>& v) {
    return std::all_of(v.begin(), v.end(), [](float x) { return x >= 0.f && x <= 1.f; });
  }

  // Appends bytes at a 4-byte aligned offset of the current buffer; returns the view index.
  int add_view(const void* bytes, std::size_t size, int target) {
    std::vector<unsigned char>& data = data_[std::size_t(buffer_)];
    while (data.size() % 4 != 0) data.push_back(0);
    tinygltf::BufferView v;
    v.buffer = buffer_;
    v.byteOffset = data.size();
    v.byteLength = size;
    v.target = target;
    const auto* b = static_cast<const unsigned char*>(bytes);
    data.insert(data.end(), b, b + size);
    m_.bufferViews.push_back(v);
    return static_cast<int>(m_.bufferViews.size() - 1);
  }

  static int type_for(int components) {
    switch (components) {
      case 1:
        return TINYGLTF_TYPE_SCALAR;
      case 2:
        return TINYGLTF_TYPE_VEC2;
      case 3:
        return TINYGLTF_TYPE_VEC3;
      default:
        return TINYGLTF_TYPE_VEC4;
    }
  }

  // A FLOAT accessor; with `view` < 0 it has no buffer view (Draco).
  int float_accessor(const std::vector<float>& values, int components, std::size_t count, int view,
                     bool min_max) {
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
    return float_accessor(values, components, values.size() / static_cast<std::size_t>(components), view,
                          min_max);
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

  // Tangents serve normal maps only (TEAM decision): without one they are dead weight (a quarter
  // of a mesh's vertex bytes).
  bool writes_tangents(const Primitive& p) const {
    return !p.tangents.empty() && p.material >= 0 &&
           s_.materials[std::size_t(p.material)].normal_texture.image >= 0;
  }

  tinygltf::Primitive plain_primitive(const Primitive& p) {
    tinygltf::Primitive out;
    const int t = TINYGLTF_TARGET_ARRAY_BUFFER;
    const Grid& grid = grids_[mesh_index_];
    const double float_error =
        quantize_ && o_.meshopt && mesh_index_ < o_.quantize.float_position_error.size()
            ? o_.quantize.float_position_error[mesh_index_]
            : 0.0;
    out.attributes["POSITION"] = grid.bits > 0     ? quantized_positions(p.positions, grid)
                                 : float_error > 0 ? exponential_positions(p.positions, float_error)
                                                   : float_attribute(p.positions, 3, true, t);
    if (!p.normals.empty())
      out.attributes["NORMAL"] =
          quantize_ ? quantized_normals(p.normals) : float_attribute(p.normals, 3, false, t);
    if (writes_tangents(p)) out.attributes["TANGENT"] = float_attribute(p.tangents, 4, false, t);
    if (!p.texcoords.empty())
      out.attributes["TEXCOORD_0"] = quantize_ && p.material >= 0 && uv_grid_[std::size_t(p.material)]
                                         ? grid_texcoords(p.texcoords)
                                     : quantize_ && in_unit_range(p.texcoords)
                                         ? quantized_unorm(p.texcoords, 2, o_.quantize.texcoord_bits, false)
                                         : float_attribute(p.texcoords, 2, false, t);
    if (!p.colors.empty())
      out.attributes["COLOR_0"] = quantize_ ? quantized_unorm(p.colors, 4, o_.quantize.color_bits, true)
                                            : float_attribute(p.colors, 4, false, t);
    for (const CustomAttribute* a : sorted_custom(p))
      out.attributes[a->name] = float_attribute(a->values, a->components, false, t);
    if (!p.indices.empty()) out.indices = index_accessor(p.indices, p.vertex_count());
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
    const int mesh_buffer = buffer_;
    for (const Primitive& p : in.primitives) {
      buffer_ = external_ && p.buffer >= 0 ? p.buffer : mesh_buffer;
      tinygltf::Primitive gp =
          o_.draco.enabled && p.mode == PrimitiveMode::kTriangles ? draco_primitive(p) : plain_primitive(p);
      gp.mode = static_cast<int>(p.mode);
      gp.material = p.material >= 0 ? material_index_[std::size_t(p.material)] : -1;
      if (!p.extras.is_null()) gp.extras = to_value(p.extras);
      out.primitives.push_back(std::move(gp));
    }
    buffer_ = mesh_buffer;
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
      used_.insert(kTextureTransform);
      required_.insert(kTextureTransform);
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
      const Grid& g = grids_[std::size_t(in.mesh)];
      const std::array<double, 3> o = rotate(in.rotation, {s[0] * g.lo[0], s[1] * g.lo[1], s[2] * g.lo[2]});
      for (std::size_t c = 0; c < 3; ++c) t[c] += o[c], s[c] *= g.step;
    }
    const int parent = parent_[index];
    const int parent_mesh = parent >= 0 ? s_.nodes[std::size_t(parent)].mesh : -1;
    if (parent_mesh >= 0 && grids_[std::size_t(parent_mesh)].bits > 0) {
      const Grid& g = grids_[std::size_t(parent_mesh)];
      for (std::size_t c = 0; c < 3; ++c) t[c] = (t[c] - g.lo[c]) / g.step, s[c] /= g.step;
    }
    if (t != std::array<double, 3>{0, 0, 0}) out.translation.assign(t.begin(), t.end());
    if (in.rotation != std::array<double, 4>{0, 0, 0, 1})
      out.rotation.assign(in.rotation.begin(), in.rotation.end());
    if (s != std::array<double, 3>{1, 1, 1}) out.scale.assign(s.begin(), s.end());
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
  bool external_ = false;
  bool quantize_ = false;
  std::size_t mesh_index_ = 0;  // the mesh being built
  std::vector<Grid> grids_;     // per mesh
  std::vector<int> parent_;     // per node, -1 = root
  std::vector<char> uv_grid_;   // per material: its uvs on the texcoord grid (KHR_texture_transform)
  std::map<int, std::string> filters_;
  int buffer_ = 0;                                // buffer the next view goes to
  std::vector<std::vector<unsigned char>> data_;  // per buffer
  std::vector<int> used_materials_, used_images_, material_index_, image_index_;
  std::vector<EncodedFile> resources_;
  std::vector<std::size_t> buffer_sizes_;
  std::set<std::string> used_, required_;
  std::map<std::pair<int, int>, int> samplers_, textures_;
};

void check_scene(const Scene& scene) {
  const std::vector<std::string> problems = validate_scene(scene);
  if (!problems.empty()) {
    std::string msg = "invalid glTF scene: " + problems.front();
    if (problems.size() > 1) msg += " (and " + std::to_string(problems.size() - 1) + " more problems)";
    throw GltfError(msg);
  }
}

}  // namespace

const char* extension(FileFormat format) { return format == FileFormat::kGlb ? ".glb" : ".gltf"; }

void encode_to(const Scene& scene, std::ostream& out, const WriteOptions& options) {
  if (options.format == FileFormat::kGltfExternal)
    throw GltfError("an external .gltf is several files: use encode_external()");
  check_scene(scene);
  if (options.meshopt && (options.format != FileFormat::kGlb || options.draco.enabled))
    throw GltfError("EXT_meshopt_compression is written to GLB files without Draco only");
  ModelBuilder builder(scene, options);
  tinygltf::Model model = builder.build();
  if (options.meshopt) {
    const std::string bytes =
        detail::encode_meshopt_glb(model, builder.view_filters(), options.meshopt_merge_views);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return;
  }
  tinygltf::TinyGLTF writer;
  const bool glb = options.format == FileFormat::kGlb;
  if (!writer.WriteGltfSceneToStream(&model, out, /*prettyPrint=*/!glb, /*writeBinary=*/glb))
    throw GltfError("tinygltf could not serialise the scene");
}

std::string encode(const Scene& scene, const WriteOptions& options) {
  std::ostringstream out(std::ios::binary);
  encode_to(scene, out, options);
  return std::move(out).str();
}

EncodedFiles encode_external(const Scene& scene, const WriteOptions& options) {
  check_scene(scene);
  WriteOptions o = options;
  o.format = FileFormat::kGltfExternal;
  ModelBuilder builder(scene, o);
  tinygltf::Model model = builder.build();
  tinygltf::TinyGLTF writer;
  std::ostringstream out(std::ios::binary);
  if (!writer.WriteGltfSceneToStream(&model, out, /*prettyPrint=*/true, /*writeBinary=*/false))
    throw GltfError("tinygltf could not serialise the scene");
  // tinygltf's stream writer embeds every buffer as a data URI (here: empty ones) and gives
  // images without a buffer view no uri; name the files instead. nlohmann keeps keys sorted, so
  // the text stays deterministic.
  nlohmann::json j = nlohmann::json::parse(std::move(out).str());
  const std::vector<std::size_t>& sizes = builder.buffer_sizes();
  for (std::size_t b = 0; b < sizes.size(); ++b)
    j["buffers"][b] = {{"byteLength", sizes[b]}, {"uri", model.buffers[b].uri}};
  for (std::size_t i = 0; i < model.images.size(); ++i) {
    const tinygltf::Image& im = model.images[i];
    if (im.uri.empty()) continue;
    nlohmann::json& ji = j["images"][i];
    ji.erase("bufferView");
    ji["uri"] = im.uri;
    ji["mimeType"] = im.mimeType;
  }
  EncodedFiles files;
  files.gltf = j.dump(2) + "\n";
  files.resources = builder.take_resources();
  return files;
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
