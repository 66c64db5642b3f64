// Appending one scene to another with shared images and materials (compose.h).
#include "libs/gltf/compose.h"

#include <algorithm>

namespace sylva::gltf {

namespace {

bool same_texture(const TextureRef& a, const TextureRef& b) {
  return a.image == b.image && a.wrap_s == b.wrap_s && a.wrap_t == b.wrap_t;
}

bool same_material(const Material& a, const Material& b) {
  return a.name == b.name && a.base_color == b.base_color &&
         same_texture(a.base_color_texture, b.base_color_texture) &&
         same_texture(a.normal_texture, b.normal_texture) && a.metallic == b.metallic &&
         a.roughness == b.roughness && a.alpha_mode == b.alpha_mode && a.alpha_cutoff == b.alpha_cutoff &&
         a.double_sided == b.double_sided && a.unlit == b.unlit && a.extras == b.extras;
}

}  // namespace

std::vector<int> append_scene(Scene& into, const Scene& from) {
  std::vector<int> image_map(from.images.size(), -1);
  for (std::size_t i = 0; i < from.images.size(); ++i) {
    const Image& im = from.images[i];
    for (std::size_t j = 0; j < into.images.size() && image_map[i] < 0; ++j) {
      const Image& e = into.images[j];
      if (e.name == im.name && e.mime_type == im.mime_type && e.bytes == im.bytes) image_map[i] = int(j);
    }
    if (image_map[i] < 0) {
      image_map[i] = int(into.images.size());
      Image copy = im;
      copy.uri.clear();  // a resource of `from`'s file layout, not of `into`'s
      into.images.push_back(std::move(copy));
    }
  }
  auto remap_texture = [&](TextureRef t) {
    if (t.image >= 0 && std::size_t(t.image) < image_map.size()) t.image = image_map[std::size_t(t.image)];
    return t;
  };
  std::vector<int> material_map(from.materials.size(), -1);
  for (std::size_t i = 0; i < from.materials.size(); ++i) {
    Material m = from.materials[i];
    m.base_color_texture = remap_texture(m.base_color_texture);
    m.normal_texture = remap_texture(m.normal_texture);
    for (std::size_t j = 0; j < into.materials.size() && material_map[i] < 0; ++j)
      if (same_material(into.materials[j], m)) material_map[i] = int(j);
    if (material_map[i] < 0) {
      material_map[i] = int(into.materials.size());
      into.materials.push_back(std::move(m));
    }
  }
  const int mesh_base = int(into.meshes.size());
  for (const Mesh& m : from.meshes) {
    Mesh copy = m;
    copy.buffer = 0;
    for (Primitive& p : copy.primitives) {
      p.buffer = -1;
      if (p.material >= 0 && std::size_t(p.material) < material_map.size())
        p.material = material_map[std::size_t(p.material)];
    }
    into.meshes.push_back(std::move(copy));
  }
  const int node_base = int(into.nodes.size());
  for (const Node& n : from.nodes) {
    Node copy = n;
    if (copy.mesh >= 0) copy.mesh += mesh_base;
    for (int& c : copy.children) c += node_base;
    into.nodes.push_back(std::move(copy));
  }
  for (const std::string& e : from.extensions_required)
    if (std::find(into.extensions_required.begin(), into.extensions_required.end(), e) ==
        into.extensions_required.end())
      into.extensions_required.push_back(e);
  std::vector<int> roots;
  for (int r : from.roots) roots.push_back(r + node_base);
  return roots;
}

}  // namespace sylva::gltf
