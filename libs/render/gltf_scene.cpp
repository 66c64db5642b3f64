// glTF -> render::Scene. tinygltf parses the file (and decodes PNG/JPEG images with stb, as
// Debian's libtinygltf is built); this file turns accessors into typed arrays, decodes Draco
// primitives, expands strips and fans, flattens the node hierarchy and instancing into world
// matrices, and checks every index so the GL side never reads out of bounds.
//
// tinygltf comes from Debian's shared library (TinyGLTF::TinyGLTF), which already contains the
// implementation: no translation unit here defines TINYGLTF_IMPLEMENTATION, so other sylva
// libraries can link the same library without duplicate symbols.
#include "libs/render/gltf_scene.h"

#include <draco/compression/decode.h>
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "libs/render/meshopt_decode.h"

namespace sylva::render {
namespace {

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";
constexpr const char* kUnlit = "KHR_materials_unlit";
constexpr const char* kTextureTransform = "KHR_texture_transform";

const std::set<std::string>& supported_required_extensions() {
  static const std::set<std::string> s = {kDraco, kInstancing, kUnlit, "KHR_mesh_quantization",
                                          kTextureTransform};
  return s;
}

// Optional extensions whose effect the renderer draws, or that do not change the picture.
// Any other extension a file uses is drawn without its effect, with a warning
// (Scene::warnings; issue 15: KHR_texture_transform used to be ignored silently).
const std::set<std::string>& understood_extensions() {
  static const std::set<std::string> s = {kDraco,
                                          kInstancing,
                                          kUnlit,
                                          "KHR_mesh_quantization",
                                          kTextureTransform,
                                          "MSFT_lod",
                                          "MSFT_texture_dds",
                                          "KHR_materials_emissive_strength"};
  return s;
}

// tinygltf reports several problems as newline-separated text; keep one line.
std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  std::string out;
  for (char c : s) {
    if (c == '\n') {
      out += "; ";
    } else {
      out += c;
    }
  }
  return out;
}

// Values of one attribute, `components` floats per element.
struct AttributeData {
  int components = 0;
  std::size_t count = 0;
  std::vector<float> values;
};

class Loader {
 public:
  Loader(const tinygltf::Model& model, std::string file, std::filesystem::path base_dir)
      : m_(model), file_(std::move(file)), base_dir_(std::move(base_dir)) {}

  Scene load() {
    check_extensions();
    check_images();
    scene_.source = file_;
    scene_.warnings = ignored_extensions();
    load_textures_and_materials();
    const Mat4 identity = Mat4::Identity();
    for (int root : root_nodes()) visit(root, identity, 0);
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& why) const { throw SceneLoadError(file_ + ": error: " + why); }

  // ---- 1. Whole-file checks ------------------------------------------------------------------

  void check_extensions() const {
    for (const std::string& ext : m_.extensionsRequired) {
      if (!supported_required_extensions().count(ext))
        fail("requires unsupported glTF extension '" + ext + "'");
    }
  }

  std::vector<std::string> ignored_extensions() const {
    std::vector<std::string> out;
    for (const std::string& ext : m_.extensionsUsed)
      if (!understood_extensions().count(ext))
        out.push_back(file_ + ": warning: uses glTF extension '" + ext +
                      "', which sylva's renderer ignores: the image may differ from other viewers'");
    return out;
  }

  // Every image must have decoded; all the missing ones are named in one message.
  void check_images() const {
    std::string problems;
    for (std::size_t i = 0; i < m_.images.size(); ++i) {
      const tinygltf::Image& img = m_.images[i];
      if (!img.image.empty() && img.width > 0 && img.height > 0) continue;
      const std::string label = !img.uri.empty() ? img.uri : (!img.name.empty() ? img.name : "embedded");
      std::string why = warnings_for(i);
      if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0) {
        const std::filesystem::path file = base_dir_ / decode_uri(img.uri);
        std::error_code ec;
        if (!std::filesystem::exists(file, ec)) why = "no such file " + file.string();
      }
      if (!problems.empty()) problems += "; ";
      problems += "texture '" + label + "' (image " + std::to_string(i) + ") could not be loaded" +
                  (why.empty() ? std::string() : ": " + why);
    }
    if (!problems.empty()) fail(problems);
  }

 public:
  std::string warnings;  // tinygltf's warnings, searched for the reason an image is missing

 private:
  std::string warnings_for(std::size_t image) const {
    const std::string key = "image[" + std::to_string(image) + "]";
    std::size_t at = warnings.find(key);
    if (at == std::string::npos) return {};
    std::size_t begin = warnings.rfind('\n', at);
    begin = begin == std::string::npos ? 0 : begin + 1;
    std::size_t end = warnings.find('\n', at);
    return warnings.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
  }

  // ---- 2. Textures and materials -------------------------------------------------------------

  static Wrap to_wrap(int w) {
    switch (w) {
      case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
        return Wrap::kClampToEdge;
      case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
        return Wrap::kMirroredRepeat;
      default:
        return Wrap::kRepeat;
    }
  }

  Texture make_texture(int texture_index) const {
    const tinygltf::Texture& t = m_.textures[std::size_t(texture_index)];
    if (t.source < 0 || std::size_t(t.source) >= m_.images.size())
      fail("texture " + std::to_string(texture_index) + " has no valid image source");
    const tinygltf::Image& img = m_.images[std::size_t(t.source)];
    Texture out;
    out.name =
        !img.uri.empty() ? img.uri : (!img.name.empty() ? img.name : "image " + std::to_string(t.source));
    out.width = img.width;
    out.height = img.height;
    const int comps = img.component;
    const int bytes_per = img.bits == 16 ? 2 : 1;
    if (comps < 1 || comps > 4 || (img.bits != 8 && img.bits != 16) ||
        img.image.size() < std::size_t(img.width) * std::size_t(img.height) * std::size_t(comps * bytes_per))
      fail("texture '" + out.name + "' has an unsupported pixel layout");
    out.rgba.resize(std::size_t(img.width) * std::size_t(img.height) * 4);
    for (std::size_t i = 0, n = std::size_t(img.width) * std::size_t(img.height); i < n; ++i) {
      std::uint8_t px[4] = {0, 0, 0, 255};
      for (int c = 0; c < comps; ++c) {
        // 16-bit samples are little-endian in memory (stb); keep the high byte.
        const std::size_t at = (i * std::size_t(comps) + std::size_t(c)) * std::size_t(bytes_per);
        px[c] = bytes_per == 2 ? img.image[at + 1] : img.image[at];
      }
      if (comps <= 2) {  // grey (+ alpha)
        const std::uint8_t a = comps == 2 ? px[1] : 255;
        px[1] = px[2] = px[0];
        px[3] = a;
      }
      std::memcpy(&out.rgba[i * 4], px, 4);
    }
    if (t.sampler >= 0 && std::size_t(t.sampler) < m_.samplers.size()) {
      const tinygltf::Sampler& s = m_.samplers[std::size_t(t.sampler)];
      out.wrap_s = to_wrap(s.wrapS);
      out.wrap_t = to_wrap(s.wrapT);
      out.mag_filter = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST ? Filter::kNearest : Filter::kLinear;
      switch (s.minFilter) {
        case TINYGLTF_TEXTURE_FILTER_NEAREST:
          out.min_filter = Filter::kNearest;
          out.mipmaps = false;
          break;
        case TINYGLTF_TEXTURE_FILTER_LINEAR:
          out.min_filter = Filter::kLinear;
          out.mipmaps = false;
          break;
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
          out.min_filter = Filter::kNearest;
          out.mipmaps = true;
          break;
        default:
          out.min_filter = Filter::kLinear;
          out.mipmaps = true;
          break;
      }
    }
    return out;
  }

  void load_textures_and_materials() {
    std::map<int, int> texture_slot;  // glTF texture index -> Scene::textures index
    for (std::size_t i = 0; i < m_.materials.size(); ++i) {
      const tinygltf::Material& gm = m_.materials[i];
      Material mat;
      mat.name = gm.name;
      const auto& f = gm.pbrMetallicRoughness.baseColorFactor;
      if (f.size() == 4) mat.base_color = Vec4(float(f[0]), float(f[1]), float(f[2]), float(f[3]));
      const int tex = gm.pbrMetallicRoughness.baseColorTexture.index;
      if (tex >= 0) {
        if (std::size_t(tex) >= m_.textures.size())
          fail("material " + std::to_string(i) + " names texture " + std::to_string(tex) +
               ", which does not exist");
        auto [it, inserted] = texture_slot.emplace(tex, int(scene_.textures.size()));
        if (inserted) scene_.textures.push_back(make_texture(tex));
        mat.base_color_texture = it->second;
      }
      texcoord_set_.push_back(gm.pbrMetallicRoughness.baseColorTexture.texCoord);
      uv_transform_.push_back(
          texture_transform(gm.pbrMetallicRoughness.baseColorTexture, texcoord_set_.back()));
      if (gm.alphaMode == "MASK") {
        mat.alpha_mode = AlphaMode::kMask;
      } else if (gm.alphaMode == "BLEND") {
        mat.alpha_mode = AlphaMode::kBlend;
      }
      mat.alpha_cutoff = float(gm.alphaCutoff);
      mat.double_sided = gm.doubleSided;
      mat.unlit = gm.extensions.count(kUnlit) > 0;
      scene_.materials.push_back(std::move(mat));
    }
  }

  // KHR_texture_transform of a texture reference: uv' = offset + R(rotation) (scale * uv), the
  // spec's translation * rotation * scale (rotation counter-clockwise: u' = c u - s v,
  // v' = s u + c v); its texCoord replaces the reference's set.
  struct UvTransform {
    bool identity = true;
    float offset[2] = {0, 0}, scale[2] = {1, 1}, rotation = 0;
    Vec2 apply(Vec2 uv) const {
      if (identity) return uv;
      const float u = uv.x() * scale[0], v = uv.y() * scale[1], c = std::cos(rotation),
                  s = std::sin(rotation);
      return Vec2(offset[0] + c * u - s * v, offset[1] + s * u + c * v);
    }
  };
  static UvTransform texture_transform(const tinygltf::TextureInfo& info, int& texcoord_set) {
    UvTransform t;
    const auto it = info.extensions.find(kTextureTransform);
    if (it == info.extensions.end() || !it->second.IsObject()) return t;
    const tinygltf::Value& e = it->second;
    auto pair = [&](const char* key, float* out) {
      if (!e.Has(key) || !e.Get(key).IsArray() || e.Get(key).ArrayLen() != 2) return;
      for (int k = 0; k < 2; ++k) out[k] = float(e.Get(key).Get(k).GetNumberAsDouble());
    };
    pair("offset", t.offset);
    pair("scale", t.scale);
    if (e.Has("rotation") && e.Get("rotation").IsNumber())
      t.rotation = float(e.Get("rotation").GetNumberAsDouble());
    if (e.Has("texCoord") && e.Get("texCoord").IsInt()) texcoord_set = e.Get("texCoord").GetNumberAsInt();
    t.identity = false;
    return t;
  }

  // ---- 3. Accessors --------------------------------------------------------------------------

  static float component(const unsigned char* p, int type, bool normalized) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        const float v = float(*p);
        return normalized ? v / 255.f : v;
      }
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const float v = float(std::int8_t(*p));
        return normalized ? std::max(v / 127.f, -1.f) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? float(v) / 65535.f : float(v);
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(float(v) / 32767.f, -1.f) : float(v);
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return float(v);
      }
      default:
        return 0.f;
    }
  }

  const tinygltf::BufferView& buffer_view(int view, const std::string& what) const {
    if (view < 0 || std::size_t(view) >= m_.bufferViews.size())
      fail(what + ": buffer view " + std::to_string(view) + " does not exist");
    return m_.bufferViews[std::size_t(view)];
  }

  // Checks that `count` elements of `elem_size` bytes at `stride` fit in the buffer view.
  const unsigned char* view_data(int view, std::size_t offset, std::size_t count, std::size_t stride,
                                 std::size_t elem_size, const std::string& what) const {
    const tinygltf::BufferView& bv = buffer_view(view, what);
    if (bv.buffer < 0 || std::size_t(bv.buffer) >= m_.buffers.size())
      fail(what + ": buffer " + std::to_string(bv.buffer) + " does not exist");
    const tinygltf::Buffer& buf = m_.buffers[std::size_t(bv.buffer)];
    if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
      fail(what + ": buffer view runs past the end of its buffer");
    // Overflow-safe form of offset + stride * (count - 1) + elem_size <= byteLength.
    if (count > 0 && (stride == 0 || offset > bv.byteLength || elem_size > bv.byteLength - offset ||
                      (count - 1) > (bv.byteLength - offset - elem_size) / stride))
      fail(what + ": data runs past the end of its buffer view");
    return buf.data.data() + bv.byteOffset + offset;
  }

  AttributeData read_accessor(int index, const std::string& what) const {
    if (index < 0 || std::size_t(index) >= m_.accessors.size())
      fail(what + ": accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor& acc = m_.accessors[std::size_t(index)];
    const int ncomp = tinygltf::GetNumComponentsInType(std::uint32_t(acc.type));
    const int csize = tinygltf::GetComponentSizeInBytes(std::uint32_t(acc.componentType));
    if (ncomp <= 0 || csize <= 0 || ncomp > 16)
      fail(what + ": accessor " + std::to_string(index) + " has an invalid type");
    const std::size_t elem = std::size_t(ncomp) * std::size_t(csize);
    // Check the data range before allocating: a corrupt count must not allocate gigabytes.
    const unsigned char* base = nullptr;
    std::size_t stride = elem;
    if (acc.bufferView >= 0) {
      if (buffer_view(acc.bufferView, what).byteStride) stride = buffer_view(acc.bufferView, what).byteStride;
      base = view_data(acc.bufferView, acc.byteOffset, acc.count, stride, elem, what);
    } else if (acc.count > (std::size_t(1) << 28)) {
      fail(what + ": accessor " + std::to_string(index) + " has an implausible count " +
           std::to_string(acc.count));
    }
    AttributeData out;
    out.components = ncomp;
    out.count = acc.count;
    out.values.assign(acc.count * std::size_t(ncomp), 0.f);
    if (base) {
      for (std::size_t i = 0; i < acc.count; ++i)
        for (int c = 0; c < ncomp; ++c)
          out.values[i * std::size_t(ncomp) + std::size_t(c)] =
              component(base + i * stride + std::size_t(c * csize), acc.componentType, acc.normalized);
    }
    if (acc.sparse.isSparse) {
      const std::size_t n = std::size_t(std::max(acc.sparse.count, 0));
      const int itype = acc.sparse.indices.componentType;
      const int isize = tinygltf::GetComponentSizeInBytes(std::uint32_t(itype));
      if (isize <= 0) fail(what + ": sparse accessor has invalid index type");
      const unsigned char* idx =
          view_data(acc.sparse.indices.bufferView, std::size_t(acc.sparse.indices.byteOffset), n,
                    std::size_t(isize), std::size_t(isize), what);
      const unsigned char* val = view_data(acc.sparse.values.bufferView,
                                           std::size_t(acc.sparse.values.byteOffset), n, elem, elem, what);
      for (std::size_t k = 0; k < n; ++k) {
        const auto target = std::size_t(component(idx + k * std::size_t(isize), itype, false));
        if (target >= acc.count) fail(what + ": sparse index out of range");
        for (int c = 0; c < ncomp; ++c)
          out.values[target * std::size_t(ncomp) + std::size_t(c)] =
              component(val + k * elem + std::size_t(c * csize), acc.componentType, acc.normalized);
      }
    }
    return out;
  }

  std::vector<std::uint32_t> read_indices(int index, const std::string& what) const {
    const tinygltf::Accessor& acc = m_.accessors.at(std::size_t(index));
    if (acc.type != TINYGLTF_TYPE_SCALAR || (acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                             acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                             acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
      fail(what + ": indices must be unsigned byte, short or int scalars");
    // UNSIGNED_INT values above 2^24 do not survive a float; read integers directly.
    const int csize = tinygltf::GetComponentSizeInBytes(std::uint32_t(acc.componentType));
    std::vector<std::uint32_t> out(acc.count, 0);
    if (acc.bufferView < 0 || acc.sparse.isSparse) {
      const AttributeData a = read_accessor(index, what);
      for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::uint32_t(a.values[i]);
      return out;
    }
    const std::size_t stride = buffer_view(acc.bufferView, what).byteStride
                                   ? buffer_view(acc.bufferView, what).byteStride
                                   : std::size_t(csize);
    const unsigned char* base =
        view_data(acc.bufferView, acc.byteOffset, acc.count, stride, std::size_t(csize), what);
    for (std::size_t i = 0; i < acc.count; ++i) {
      const unsigned char* p = base + i * stride;
      if (csize == 1) {
        out[i] = *p;
      } else if (csize == 2) {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        out[i] = v;
      } else {
        std::memcpy(&out[i], p, 4);
      }
    }
    return out;
  }

  // ---- 4. Primitives -------------------------------------------------------------------------

  // Attributes of a Draco-compressed primitive, decoded once.
  struct DracoData {
    std::map<std::string, AttributeData> attributes;
    std::vector<std::uint32_t> indices;
    bool has_faces = false;
  };

  DracoData decode_draco(const tinygltf::Value& ext, const std::string& what) const {
    if (!ext.IsObject() || !ext.Has("bufferView") || !ext.Has("attributes"))
      fail(what + ": " + kDraco + " needs 'bufferView' and 'attributes'");
    const int view = ext.Get("bufferView").GetNumberAsInt();
    if (view < 0 || std::size_t(view) >= m_.bufferViews.size())
      fail(what + ": Draco buffer view " + std::to_string(view) + " does not exist");
    const std::size_t len = m_.bufferViews[std::size_t(view)].byteLength;
    const unsigned char* data = view_data(view, 0, 1, len, len, what);

    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(data), len);
    auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok()) fail(what + ": cannot decode Draco data: " + type.status().error_msg_string());
    draco::Decoder decoder;
    std::unique_ptr<draco::PointCloud> cloud;
    DracoData out;
    if (type.value() == draco::TRIANGULAR_MESH) {
      auto mesh = decoder.DecodeMeshFromBuffer(&buffer);
      if (!mesh.ok()) fail(what + ": cannot decode Draco mesh: " + mesh.status().error_msg_string());
      std::unique_ptr<draco::Mesh> dm = std::move(mesh).value();
      out.has_faces = true;
      out.indices.reserve(std::size_t(dm->num_faces()) * 3);
      for (draco::FaceIndex f(0); f < dm->num_faces(); ++f)
        for (int k = 0; k < 3; ++k) out.indices.push_back(dm->face(f)[k].value());
      cloud = std::move(dm);
    } else if (type.value() == draco::POINT_CLOUD) {
      auto pc = decoder.DecodePointCloudFromBuffer(&buffer);
      if (!pc.ok()) fail(what + ": cannot decode Draco point cloud: " + pc.status().error_msg_string());
      cloud = std::move(pc).value();
    } else {
      fail(what + ": unknown Draco geometry type");
    }
    const tinygltf::Value& attrs = ext.Get("attributes");
    for (const std::string& name : attrs.Keys()) {
      const int uid = attrs.Get(name).GetNumberAsInt();
      const draco::PointAttribute* pa = cloud->GetAttributeByUniqueId(std::uint32_t(uid));
      if (!pa) fail(what + ": Draco attribute " + name + " (id " + std::to_string(uid) + ") is missing");
      AttributeData a;
      a.components = pa->num_components();
      a.count = cloud->num_points();
      a.values.resize(a.count * std::size_t(a.components));
      for (draco::PointIndex i(0); i < cloud->num_points(); ++i) {
        if (!pa->ConvertValue<float>(pa->mapped_index(i), std::int8_t(a.components),
                                     &a.values[std::size_t(i.value()) * std::size_t(a.components)]))
          fail(what + ": Draco attribute " + name + " cannot be converted to float");
      }
      out.attributes.emplace(name, std::move(a));
    }
    return out;
  }

  // Expands strips, fans and loops into lists.
  static std::vector<std::uint32_t> expand(int mode, const std::vector<std::uint32_t>& in) {
    std::vector<std::uint32_t> out;
    switch (mode) {
      case TINYGLTF_MODE_TRIANGLE_STRIP:
        for (std::size_t i = 2; i < in.size(); ++i) {
          if (i % 2 == 0) {
            out.insert(out.end(), {in[i - 2], in[i - 1], in[i]});
          } else {
            out.insert(out.end(), {in[i - 1], in[i - 2], in[i]});
          }
        }
        return out;
      case TINYGLTF_MODE_TRIANGLE_FAN:
        for (std::size_t i = 2; i < in.size(); ++i) out.insert(out.end(), {in[i - 1], in[i], in[0]});
        return out;
      case TINYGLTF_MODE_LINE_STRIP:
        for (std::size_t i = 1; i < in.size(); ++i) out.insert(out.end(), {in[i - 1], in[i]});
        return out;
      case TINYGLTF_MODE_LINE_LOOP:
        for (std::size_t i = 1; i < in.size(); ++i) out.insert(out.end(), {in[i - 1], in[i]});
        if (in.size() > 2) out.insert(out.end(), {in.back(), in.front()});
        return out;
      case TINYGLTF_MODE_TRIANGLES:
        out = in;
        out.resize(out.size() / 3 * 3);
        return out;
      case TINYGLTF_MODE_LINE:
        out = in;
        out.resize(out.size() / 2 * 2);
        return out;
      default:
        return in;
    }
  }

  Primitive load_primitive(const tinygltf::Primitive& gp, const std::string& what) const {
    Primitive p;
    switch (gp.mode) {
      case TINYGLTF_MODE_POINTS:
        p.topology = Topology::kPoints;
        break;
      case TINYGLTF_MODE_LINE:
      case TINYGLTF_MODE_LINE_LOOP:
      case TINYGLTF_MODE_LINE_STRIP:
        p.topology = Topology::kLines;
        break;
      case TINYGLTF_MODE_TRIANGLES:
      case TINYGLTF_MODE_TRIANGLE_STRIP:
      case TINYGLTF_MODE_TRIANGLE_FAN:
        p.topology = Topology::kTriangles;
        break;
      default:
        fail(what + ": unknown primitive mode " + std::to_string(gp.mode));
    }
    if (gp.material >= 0 && std::size_t(gp.material) >= m_.materials.size())
      fail(what + ": material " + std::to_string(gp.material) + " does not exist");
    p.material = gp.material;

    std::optional<DracoData> draco;
    if (auto it = gp.extensions.find(kDraco); it != gp.extensions.end())
      draco = decode_draco(it->second, what);

    // An attribute from the Draco block if it is there, else from its accessor.
    auto fetch = [&](const std::string& name) -> std::optional<AttributeData> {
      if (draco) {
        if (auto d = draco->attributes.find(name); d != draco->attributes.end()) return d->second;
      }
      auto a = gp.attributes.find(name);
      if (a == gp.attributes.end()) return std::nullopt;
      return read_accessor(a->second, what + " attribute " + name);
    };

    const std::optional<AttributeData> pos = fetch("POSITION");
    if (!pos) fail(what + ": has no POSITION attribute");
    if (pos->components != 3) fail(what + ": POSITION must be VEC3");
    const std::size_t n = pos->count;
    auto check = [&](const AttributeData& a, const std::string& name, std::initializer_list<int> comps) {
      if (a.count != n)
        fail(what + ": " + name + " has " + std::to_string(a.count) + " elements, POSITION has " +
             std::to_string(n));
      if (std::find(comps.begin(), comps.end(), a.components) == comps.end())
        fail(what + ": " + name + " has " + std::to_string(a.components) + " components per element");
    };
    p.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      p.positions[i] = Vec3(pos->values[i * 3], pos->values[i * 3 + 1], pos->values[i * 3 + 2]);
    if (auto nrm = fetch("NORMAL")) {
      check(*nrm, "NORMAL", {3});
      p.normals.resize(n);
      for (std::size_t i = 0; i < n; ++i)
        p.normals[i] = Vec3(nrm->values[i * 3], nrm->values[i * 3 + 1], nrm->values[i * 3 + 2]);
    }
    if (p.material >= 0 && scene_.materials[std::size_t(p.material)].base_color_texture >= 0) {
      const std::string set = "TEXCOORD_" + std::to_string(texcoord_set_[std::size_t(p.material)]);
      if (auto uv = fetch(set)) {
        check(*uv, set, {2});
        p.texcoords.resize(n);
        const UvTransform& t = uv_transform_[std::size_t(p.material)];
        for (std::size_t i = 0; i < n; ++i)
          p.texcoords[i] = t.apply(Vec2(uv->values[i * 2], uv->values[i * 2 + 1]));
      }
    }
    if (auto col = fetch("COLOR_0")) {
      check(*col, "COLOR_0", {3, 4});
      p.colors.resize(n);
      const auto c = std::size_t(col->components);
      for (std::size_t i = 0; i < n; ++i)
        p.colors[i] = Vec4(col->values[i * c], col->values[i * c + 1], col->values[i * c + 2],
                           c == 4 ? col->values[i * c + 3] : 1.f);
    }
    if (p.topology == Topology::kPoints) {
      if (auto size = fetch(kPointSizeAttribute)) {
        check(*size, kPointSizeAttribute, {1});
        p.sizes = size->values;
      }
    }

    std::vector<std::uint32_t> raw;
    if (draco && draco->has_faces) {
      raw = draco->indices;
    } else if (gp.indices >= 0) {
      if (std::size_t(gp.indices) >= m_.accessors.size()) fail(what + ": indices accessor does not exist");
      raw = read_indices(gp.indices, what + " indices");
    } else {
      raw.resize(n);
      for (std::size_t i = 0; i < n; ++i) raw[i] = std::uint32_t(i);
    }
    for (std::uint32_t i : raw)
      if (i >= n)
        fail(what + ": index " + std::to_string(i) + " out of range (" + std::to_string(n) + " vertices)");
    p.indices = expand(draco && draco->has_faces ? TINYGLTF_MODE_TRIANGLES : gp.mode, raw);
    return p;
  }

  // ---- 5. Nodes and instancing ---------------------------------------------------------------

  std::vector<int> root_nodes() const {
    std::vector<int> roots;
    if (!m_.scenes.empty()) {
      const int s =
          m_.defaultScene >= 0 && std::size_t(m_.defaultScene) < m_.scenes.size() ? m_.defaultScene : 0;
      roots = m_.scenes[std::size_t(s)].nodes;
    } else {
      std::vector<bool> is_child(m_.nodes.size(), false);
      for (const auto& node : m_.nodes)
        for (int c : node.children)
          if (c >= 0 && std::size_t(c) < m_.nodes.size()) is_child[std::size_t(c)] = true;
      for (std::size_t i = 0; i < m_.nodes.size(); ++i)
        if (!is_child[i]) roots.push_back(int(i));
    }
    return roots;
  }

  static Mat4 trs(const Vec3& t, const Eigen::Quaternionf& r, const Vec3& s) {
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() = r.normalized().toRotationMatrix() * s.asDiagonal();
    m.topRightCorner<3, 1>() = t;
    return m;
  }

  static Mat4 local_matrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
      Mat4 m;
      for (int i = 0; i < 16; ++i) m(i % 4, i / 4) = float(node.matrix[std::size_t(i)]);
      return m;
    }
    Vec3 t = Vec3::Zero(), s = Vec3::Ones();
    Eigen::Quaternionf r = Eigen::Quaternionf::Identity();
    if (node.translation.size() == 3)
      t = Vec3(float(node.translation[0]), float(node.translation[1]), float(node.translation[2]));
    if (node.scale.size() == 3) s = Vec3(float(node.scale[0]), float(node.scale[1]), float(node.scale[2]));
    if (node.rotation.size() == 4)
      r = Eigen::Quaternionf(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]),
                             float(node.rotation[2]));
    return trs(t, r, s);
  }

  std::vector<Mat4> instance_matrices(const tinygltf::Node& node, const std::string& what) const {
    auto it = node.extensions.find(kInstancing);
    if (it == node.extensions.end()) return {Mat4::Identity()};
    const tinygltf::Value& ext = it->second;
    if (!ext.IsObject() || !ext.Has("attributes")) fail(what + ": " + kInstancing + " has no 'attributes'");
    const tinygltf::Value& attrs = ext.Get("attributes");
    std::optional<AttributeData> t, r, s;
    std::size_t count = 0;
    bool have_count = false;
    auto get = [&](const char* name, int comps, std::optional<AttributeData>& dst) {
      if (!attrs.Has(name)) return;
      dst = read_accessor(attrs.Get(name).GetNumberAsInt(), what + " instance " + name);
      if (dst->components != comps) fail(what + ": instance " + name + " has the wrong accessor type");
      if (have_count && dst->count != count) fail(what + ": instance attributes have different counts");
      count = dst->count;
      have_count = true;
    };
    get("TRANSLATION", 3, t);
    get("ROTATION", 4, r);
    get("SCALE", 3, s);
    std::vector<Mat4> out;
    out.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
      const Vec3 ti = t ? Vec3(t->values[i * 3], t->values[i * 3 + 1], t->values[i * 3 + 2]) : Vec3::Zero();
      const Vec3 si = s ? Vec3(s->values[i * 3], s->values[i * 3 + 1], s->values[i * 3 + 2]) : Vec3::Ones();
      Eigen::Quaternionf ri = Eigen::Quaternionf::Identity();
      if (r)
        ri = Eigen::Quaternionf(r->values[i * 4 + 3], r->values[i * 4], r->values[i * 4 + 1],
                                r->values[i * 4 + 2]);
      out.push_back(trs(ti, ri, si));
    }
    return out;
  }

  void visit(int index, const Mat4& parent, std::size_t depth) {
    if (index < 0 || std::size_t(index) >= m_.nodes.size())
      fail("node " + std::to_string(index) + " does not exist");
    if (depth > m_.nodes.size())
      fail("the node hierarchy contains a cycle (at node " + std::to_string(index) + ")");
    const tinygltf::Node& node = m_.nodes[std::size_t(index)];
    const Mat4 world = parent * local_matrix(node);
    if (node.mesh >= 0) {
      if (std::size_t(node.mesh) >= m_.meshes.size())
        fail("node " + std::to_string(index) + " names mesh " + std::to_string(node.mesh) +
             ", which does not exist");
      Mesh& mesh = mesh_for(node.mesh);
      for (const Mat4& inst : instance_matrices(node, "node " + std::to_string(index)))
        mesh.instances.push_back(world * inst);
    }
    for (int child : node.children) visit(child, world, depth + 1);
  }

  Mesh& mesh_for(int gltf_mesh) {
    auto [it, inserted] = mesh_slot_.emplace(gltf_mesh, scene_.meshes.size());
    if (inserted) {
      const tinygltf::Mesh& gm = m_.meshes[std::size_t(gltf_mesh)];
      Mesh mesh;
      mesh.name = gm.name;
      const std::string label =
          "mesh " + std::to_string(gltf_mesh) + (gm.name.empty() ? "" : " '" + gm.name + "'");
      for (std::size_t i = 0; i < gm.primitives.size(); ++i)
        mesh.primitives.push_back(
            load_primitive(gm.primitives[i], label + " primitive " + std::to_string(i)));
      scene_.meshes.push_back(std::move(mesh));
    }
    return scene_.meshes[it->second];
  }

  // glTF URIs are percent-encoded ("my%20bark.png").
 public:
  static std::string decode_uri(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
      if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
          std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
        out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
        i += 2;
      } else {
        out += uri[i];
      }
    }
    return out;
  }

 private:
  const tinygltf::Model& m_;
  std::string file_;
  std::filesystem::path base_dir_;
  Scene scene_;
  std::vector<int> texcoord_set_;          // per material: TEXCOORD_n of the base colour texture
  std::vector<UvTransform> uv_transform_;  // per material: of the base colour texture
  std::map<int, std::size_t> mesh_slot_;   // glTF mesh -> Scene::meshes index
};

// Debian's tinygltf 2.7.0 rejects a primitive whose `indices` accessor has no bufferView
// ("accessor[N] invalid bufferView"), which is exactly how KHR_draco_mesh_compression primitives
// are written (the indices live in the Draco stream; fixed upstream in tinygltf PR #456, 2023).
// Drop `indices` from such primitives before tinygltf sees the JSON: the Loader takes Draco
// primitives' indices from the decoded faces anyway. Returns nullopt when nothing changed or
// the JSON does not parse (tinygltf then reports the error).
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

std::uint32_t le32(const std::string& b, std::size_t at) {
  return std::uint32_t(std::uint8_t(b[at])) | std::uint32_t(std::uint8_t(b[at + 1])) << 8 |
         std::uint32_t(std::uint8_t(b[at + 2])) << 16 | std::uint32_t(std::uint8_t(b[at + 3])) << 24;
}

void put_le32(std::string& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + std::size_t(i)] = char((v >> (8 * i)) & 0xff);
}

// The same for a GLB container: rewrites its JSON chunk, keeps the binary chunk as it is.
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

// The bytes of `path` if it is a regular file (a directory, FIFO or device has no size to read);
// else nullopt and `why`: "no such file", "not a regular file" or "cannot open file".
std::optional<std::string> regular_file_bytes(const std::filesystem::path& path, std::string* why) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    *why = "no such file";
    return std::nullopt;
  }
  if (!std::filesystem::is_regular_file(path, ec)) {
    *why = "not a regular file";
    return std::nullopt;
  }
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    *why = "cannot open file";
    return std::nullopt;
  }
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

Scene load_gltf_scene(const std::filesystem::path& path) {
  const std::string file = path.string();
  auto fail = [&](const std::string& why) -> SceneLoadError {
    return SceneLoadError(file + ": error: " + why);
  };
  std::string why;
  auto bytes = regular_file_bytes(path, &why);
  if (!bytes) throw fail(why);
  return load_gltf_scene_from_memory(std::move(*bytes), file, path.parent_path());
}

namespace {

// tinygltf's file-exists test for external uris. Its own fopen()s the path, which blocks on a
// FIFO until a writer comes.
bool exists_without_opening(const std::string& path, void*) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

// tinygltf's file reader for external uris. Its own sizes its buffer from tellg(), which is -1
// for a directory that a uri may name (an allocation of 2^63 bytes).
bool read_regular_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::string why;
  auto bytes = regular_file_bytes(path, &why);
  if (!bytes) {
    if (err) *err += "cannot read '" + path + "' (" + why + ")\n";
    return false;
  }
  out->assign(bytes->begin(), bytes->end());
  return true;
}

}  // namespace

Scene load_gltf_scene_from_memory(std::string bytes, const std::string& name,
                                  const std::filesystem::path& base_dir_path) {
  const std::string& file = name;
  auto fail = [&](const std::string& why) -> SceneLoadError {
    return SceneLoadError(file + ": error: " + why);
  };
  bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (!binary) {
    // EXT_meshopt_compression over external buffers: read as the GLB of the same asset.
    const auto read_uri = [&](const std::string& uri) {
      std::string why;
      auto b = regular_file_bytes(base_dir_path / Loader::decode_uri(uri), &why);
      if (!b) throw std::runtime_error("cannot read buffer '" + uri + "' (" + why + ")");
      return std::move(*b);
    };
    try {
      if (auto glb = meshopt_gltf_as_glb(bytes, read_uri)) {
        bytes = std::move(*glb);
        binary = true;
      }
    } catch (const std::runtime_error& e) {
      throw fail(e.what());
    }
  }
  if (binary) {
    try {
      decode_meshopt_glb(bytes);
    } catch (const std::runtime_error& e) {
      throw fail(e.what());
    }
    patch_glb(bytes);
  } else if (auto patched = without_draco_index_accessors(bytes)) {
    bytes = std::move(*patched);
  }
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) throw fail("file is larger than 4 GiB");

  tinygltf::Model model;
  tinygltf::TinyGLTF reader;
  reader.SetFsCallbacks({&exists_without_opening, &tinygltf::ExpandFilePath, &read_regular_file,
                         &tinygltf::WriteWholeFile, nullptr});
  std::string err, warn;
  const std::string base_dir = base_dir_path.string();
  bool ok = false;
  try {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const auto size = static_cast<unsigned int>(bytes.size());
    ok = binary ? reader.LoadBinaryFromMemory(&model, &err, &warn, data, size, base_dir)
                : reader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, base_dir);
  } catch (const std::exception& e) {
    throw fail(std::string("invalid glTF: ") + e.what());
  }
  if (!ok) throw fail("invalid glTF: " + one_line(err.empty() ? warn : err));

  Loader loader(model, file, base_dir_path);
  loader.warnings = warn;
  try {
    return loader.load();
  } catch (const std::bad_alloc&) {
    throw fail("out of memory while loading (corrupt counts or a very large asset)");
  } catch (const std::length_error&) {
    throw fail("out of memory while loading (corrupt counts or a very large asset)");
  }
}

}  // namespace sylva::render
