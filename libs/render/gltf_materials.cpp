// Materials, their base-colour textures and the images under them (gltf_materials.h).
#include "libs/render/gltf_materials.h"

#include <cmath>
#include <cstring>
#include <map>

namespace sylva::render::detail {
namespace {

// tinygltf's warning about image `image` (why it did not load), or "".
std::string warnings_for(const std::string& warnings, std::size_t image) {
  const std::string key = "image[" + std::to_string(image) + "]";
  std::size_t at = warnings.find(key);
  if (at == std::string::npos) return {};
  std::size_t begin = warnings.rfind('\n', at);
  begin = begin == std::string::npos ? 0 : begin + 1;
  std::size_t end = warnings.find('\n', at);
  return warnings.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

Wrap to_wrap(int w) {
  switch (w) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
      return Wrap::kClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
      return Wrap::kMirroredRepeat;
    default:
      return Wrap::kRepeat;
  }
}

Texture make_texture(const GltfModel& in, int texture_index) {
  const tinygltf::Model& model = in.model();
  const tinygltf::Texture& t = model.textures[std::size_t(texture_index)];
  if (t.source < 0 || std::size_t(t.source) >= model.images.size())
    in.fail("texture " + std::to_string(texture_index) + " has no valid image source");
  const tinygltf::Image& img = model.images[std::size_t(t.source)];
  Texture out;
  out.name =
      !img.uri.empty() ? img.uri : (!img.name.empty() ? img.name : "image " + std::to_string(t.source));
  out.width = img.width;
  out.height = img.height;
  const int comps = img.component;
  const int bytes_per = img.bits == 16 ? 2 : 1;
  if (comps < 1 || comps > 4 || (img.bits != 8 && img.bits != 16) ||
      img.image.size() < std::size_t(img.width) * std::size_t(img.height) * std::size_t(comps * bytes_per))
    in.fail("texture '" + out.name + "' has an unsupported pixel layout");
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
  if (t.sampler >= 0 && std::size_t(t.sampler) < model.samplers.size()) {
    const tinygltf::Sampler& s = model.samplers[std::size_t(t.sampler)];
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

}  // namespace

void check_images(const GltfModel& in, const std::string& warnings, const std::filesystem::path& base_dir,
                  const fileio::FileSource& files) {
  const tinygltf::Model& model = in.model();
  std::string problems;
  for (std::size_t i = 0; i < model.images.size(); ++i) {
    const tinygltf::Image& img = model.images[i];
    if (!img.image.empty() && img.width > 0 && img.height > 0) continue;
    const std::string label = !img.uri.empty() ? img.uri : (!img.name.empty() ? img.name : "embedded");
    std::string why = warnings_for(warnings, i);
    if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0) {
      const std::filesystem::path file = base_dir / decode_uri(img.uri);
      if (!files.exists(file)) why = "no such file " + file.string();
    }
    if (!problems.empty()) problems += "; ";
    problems += "texture '" + label + "' (image " + std::to_string(i) + ") could not be loaded" +
                (why.empty() ? std::string() : ": " + why);
  }
  if (!problems.empty()) in.fail(problems);
}

UvTransform texture_transform(const tinygltf::TextureInfo& info, int& texcoord_set) {
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

std::vector<MaterialUv> load_materials(const GltfModel& in, Scene& scene) {
  const tinygltf::Model& model = in.model();
  std::vector<MaterialUv> uv;
  std::map<int, int> texture_slot;  // glTF texture index -> Scene::textures index
  for (std::size_t i = 0; i < model.materials.size(); ++i) {
    const tinygltf::Material& gm = model.materials[i];
    Material mat;
    mat.name = gm.name;
    const auto& f = gm.pbrMetallicRoughness.baseColorFactor;
    if (f.size() == 4) mat.base_color = Vec4(float(f[0]), float(f[1]), float(f[2]), float(f[3]));
    const int tex = gm.pbrMetallicRoughness.baseColorTexture.index;
    if (tex >= 0) {
      if (std::size_t(tex) >= model.textures.size())
        in.fail("material " + std::to_string(i) + " names texture " + std::to_string(tex) +
                ", which does not exist");
      auto [it, inserted] = texture_slot.emplace(tex, int(scene.textures.size()));
      if (inserted) scene.textures.push_back(make_texture(in, tex));
      mat.base_color_texture = it->second;
    }
    MaterialUv& u = uv.emplace_back();
    u.texcoord_set = gm.pbrMetallicRoughness.baseColorTexture.texCoord;
    u.transform = texture_transform(gm.pbrMetallicRoughness.baseColorTexture, u.texcoord_set);
    if (gm.alphaMode == "MASK") {
      mat.alpha_mode = AlphaMode::kMask;
    } else if (gm.alphaMode == "BLEND") {
      mat.alpha_mode = AlphaMode::kBlend;
    }
    mat.alpha_cutoff = float(gm.alphaCutoff);
    mat.double_sided = gm.doubleSided;
    mat.unlit = gm.extensions.count(kUnlit) > 0;
    scene.materials.push_back(std::move(mat));
  }
  return uv;
}

}  // namespace sylva::render::detail
