// glTF -> SourceGeometry (mesh_gltf.h). A straight sequence of passes:
//   1. bytes: meshopt-compressed views decoded and Draco index accessors dropped (libs/render's
//      meshopt_decode.h and gltf_draco.h: Debian's tinygltf 2.7 reads neither), then tinygltf
//      parses with its file callbacks over the sidecar files and an image loader that keeps the
//      encoded bytes (sylva stores images whole; nothing is decoded);
//   2. materials and the images their base colour textures use;
//   3. the scene's roots (or options.node), then each node's world transform and its mesh's
//      primitives, read with libs/render's checked accessor reader (GltfModel).
// libs/render's own loader (gltf_scene.h) flattens into a render::Scene with decoded textures and
// refuses missing images; an import keeps names, encoded images and goes on without a texture.
#include "stages/import/mesh_gltf.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "libs/gltf/tinygltf_files.h"
#include "libs/render/gltf_draco.h"
#include "libs/render/gltf_materials.h"
#include "libs/render/gltf_model.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/meshopt_decode.h"
#include "stages/import/mesh_checks.h"

namespace sylva::import {

namespace {

using render::detail::AttributeData;
using render::detail::GltfModel;
using Mat4 = Eigen::Matrix4d;

// The deepest node hierarchy read, as mesh_assimp.cpp's.
constexpr std::size_t kMaxNodeDepth = 1000;

const std::set<std::string>& supported_required() {
  static const std::set<std::string> s = {"KHR_draco_mesh_compression", "KHR_mesh_quantization",
                                          "KHR_texture_transform", "EXT_meshopt_compression",
                                          "KHR_materials_unlit"};
  return s;
}

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (char& c : s)
    if (c == '\n') c = ';';
  return s;
}

std::string mime_of(const std::string& bytes) {
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), "\x89PNG\r\n\x1a\n", 8) == 0) return "image/png";
  if (bytes.size() >= 3 && std::memcmp(bytes.data(), "\xFF\xD8\xFF", 3) == 0) return "image/jpeg";
  return {};
}

// tinygltf's image callback: keep the encoded bytes, decode nothing.
bool keep_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

// 1. Bytes -> tinygltf::Model. Throws MeshError.
tinygltf::Model parse(std::string bytes, std::string_view source, const SidecarFiles& files) {
  bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  try {
    if (!binary) {
      const auto read_uri = [&](const std::string& uri) {
        try {
          return files.read(files.base_dir() / render::detail::decode_uri(uri));
        } catch (const fileio::FileReadError& e) {
          throw std::runtime_error("cannot read buffer '" + uri + "' (" + e.reason() + ")");
        }
      };
      if (auto glb = render::meshopt_gltf_as_glb(bytes, read_uri)) {
        bytes = std::move(*glb);
        binary = true;
      }
    }
    if (binary) {
      render::decode_meshopt_glb(bytes);
      render::detail::patch_glb(bytes);
    } else if (auto patched = render::detail::without_draco_index_accessors(bytes)) {
      bytes = std::move(*patched);
    }
  } catch (const std::runtime_error& e) {
    throw MeshError(source, e.what());
  }
  tinygltf::Model model;
  tinygltf::TinyGLTF reader;
  reader.SetFsCallbacks(gltf::file_callbacks(files));
  reader.SetImageLoader(&keep_bytes, nullptr);
  std::string err, warn;
  bool ok = false;
  try {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const auto size = static_cast<unsigned int>(bytes.size());
    const std::string base = files.base_dir().string();
    ok = binary ? reader.LoadBinaryFromMemory(&model, &err, &warn, data, size, base)
                : reader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, base);
  } catch (const std::exception& e) {
    throw MeshError(source, std::string("invalid glTF: ") + e.what());
  }
  if (!ok) throw MeshError(source, "invalid glTF: " + one_line(err.empty() ? warn : err));
  return model;
}

std::string node_label(const tinygltf::Model& m, int i) {
  const std::string& name = m.nodes[std::size_t(i)].name;
  return "node " + std::to_string(i) + (name.empty() ? "" : " '" + name + "'");
}

Mat4 local_matrix(const tinygltf::Node& node) {
  Mat4 m = Mat4::Identity();
  if (node.matrix.size() == 16) {
    for (int i = 0; i < 16; ++i) m(i % 4, i / 4) = node.matrix[std::size_t(i)];
    return m;
  }
  Eigen::Vector3d t = Eigen::Vector3d::Zero(), s = Eigen::Vector3d::Ones();
  Eigen::Quaterniond r = Eigen::Quaterniond::Identity();
  if (node.translation.size() == 3) t = {node.translation[0], node.translation[1], node.translation[2]};
  if (node.scale.size() == 3) s = {node.scale[0], node.scale[1], node.scale[2]};
  if (node.rotation.size() == 4)
    r = Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
  if (r.norm() > 0) r.normalize();
  m.topLeftCorner<3, 3>() = r.toRotationMatrix() * s.asDiagonal();
  m.topRightCorner<3, 1>() = t;
  return m;
}

// Strips and fans as triangle lists (glTF 2.0 §3.7.2.1 vertex orders).
std::vector<std::uint32_t> expand(int mode, const std::vector<std::uint32_t>& in) {
  std::vector<std::uint32_t> out;
  if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (std::size_t i = 2; i < in.size(); ++i) {
      if (i % 2 == 0) {
        out.insert(out.end(), {in[i - 2], in[i - 1], in[i]});
      } else {
        out.insert(out.end(), {in[i - 1], in[i - 2], in[i]});
      }
    }
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (std::size_t i = 2; i < in.size(); ++i) out.insert(out.end(), {in[i - 1], in[i], in[0]});
  } else {
    out = in;
    out.resize(out.size() / 3 * 3);
  }
  return out;
}

class Reader {
 public:
  Reader(const tinygltf::Model& model, std::string_view source, const SidecarFiles& files,
         const MeshOptions& options, MeshImport& out)
      : m_(model),
        in_(model, std::string(source), std::max(options.max_vertices, options.max_triangles * 3)),
        source_(source),
        files_(files),
        options_(options),
        out_(out) {}

  void read() {
    for (const std::string& ext : m_.extensionsRequired)
      if (!supported_required().count(ext))
        throw MeshError(source_, "requires unsupported glTF extension '" + ext + "'");
    read_materials();
    for (const auto& [root, world] : roots()) visit(root, world, "", 0);
  }

 private:
  void warn(const std::string& what) { out_.warnings.push_back(std::string(source_) + ": warning: " + what); }

  // ---- 2. Materials and images ---------------------------------------------------------------

  std::string image_name(int index) const {
    const tinygltf::Image& img = m_.images[std::size_t(index)];
    if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0) return render::detail::decode_uri(img.uri);
    if (!img.name.empty()) return img.name;
    // The file name, not the path: the name goes into tree.sylt, whose bytes must not depend on
    // where the model lies.
    return std::filesystem::path(std::string(source_)).filename().string() + ".image" + std::to_string(index);
  }

  // The SourceGeometry image of texture `tex`, -1 (and a warning) when it cannot be had.
  int image_of(int tex, const std::string& material) {
    if (tex < 0 || std::size_t(tex) >= m_.textures.size() || m_.textures[std::size_t(tex)].source < 0 ||
        std::size_t(m_.textures[std::size_t(tex)].source) >= m_.images.size()) {
      warn("material '" + material + "': texture " + std::to_string(tex) +
           " has no image: the material keeps its colour");
      return -1;
    }
    const int index = m_.textures[std::size_t(tex)].source;
    if (auto it = image_slot_.find(index); it != image_slot_.end()) return it->second;
    const tinygltf::Image& img = m_.images[std::size_t(index)];
    const std::string name = image_name(index);
    std::string bytes(img.image.begin(), img.image.end());
    const std::string mime = mime_of(bytes);
    int slot = -1;
    if (bytes.empty()) {
      warn(
          "image '" + name + "' (image " + std::to_string(index) + ") of material '" + material +
          "' could not be read" +
          (img.uri.empty() || img.uri.rfind("data:", 0) == 0
               ? std::string()
               : " (no file '" +
                     files_.resolve(files_.base_dir() / name).lexically_relative(files_.base_dir()).string() +
                     "' beside the model)") +
          ": the material keeps its colour, without the texture");
    } else if (mime.empty()) {
      warn("image '" + name + "' (image " + std::to_string(index) + ") of material '" + material +
           "' is neither PNG nor JPEG: the material keeps its colour, without the texture");
    } else {
      slot = int(out_.geometry.images.size());
      out_.geometry.images.push_back({name, mime, std::move(bytes)});
    }
    image_slot_.emplace(index, slot);
    return slot;
  }

  void read_materials() {
    for (std::size_t i = 0; i < m_.materials.size(); ++i) {
      const tinygltf::Material& gm = m_.materials[i];
      tree::SourceMaterial mat;
      mat.name = gm.name.empty() ? "material" + std::to_string(i) : gm.name;
      const auto& pbr = gm.pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() == 4)
        for (std::size_t c = 0; c < 4; ++c) mat.base_color[c] = float(pbr.baseColorFactor[c]);
      mat.metallic = float(pbr.metallicFactor);
      mat.roughness = float(pbr.roughnessFactor);
      if (gm.alphaMode == "MASK") mat.alpha_mode = tree::AlphaMode::kMask;
      if (gm.alphaMode == "BLEND") mat.alpha_mode = tree::AlphaMode::kBlend;
      mat.alpha_cutoff = float(gm.alphaCutoff);
      mat.double_sided = gm.doubleSided;
      if (pbr.baseColorTexture.index >= 0)
        mat.base_color_image = image_of(pbr.baseColorTexture.index, mat.name);
      render::detail::MaterialUv& uv = uv_.emplace_back();
      uv.texcoord_set = pbr.baseColorTexture.texCoord;
      uv.transform = render::detail::texture_transform(pbr.baseColorTexture, uv.texcoord_set);
      if (pbr.baseColorTexture.index < 0) uv = {};
      out_.geometry.materials.push_back(std::move(mat));
    }
  }

  std::uint32_t default_material() {
    if (default_material_ < 0) {
      default_material_ = int(out_.geometry.materials.size());
      tree::SourceMaterial mat;
      mat.name = "default";
      out_.geometry.materials.push_back(mat);
    }
    return std::uint32_t(default_material_);
  }

  // ---- 3. Nodes ------------------------------------------------------------------------------

  // Every node's first parent (-1 for none).
  std::vector<int> parents() const {
    std::vector<int> parent(m_.nodes.size(), -1);
    for (std::size_t i = 0; i < m_.nodes.size(); ++i)
      for (int c : m_.nodes[i].children)
        if (c >= 0 && std::size_t(c) < m_.nodes.size() && parent[std::size_t(c)] < 0)
          parent[std::size_t(c)] = int(i);
    return parent;
  }

  std::vector<int> scene_roots(const std::vector<int>& parent) const {
    std::vector<int> roots;
    if (!m_.scenes.empty()) {
      const std::size_t s = m_.defaultScene >= 0 && std::size_t(m_.defaultScene) < m_.scenes.size()
                                ? std::size_t(m_.defaultScene)
                                : 0;
      roots = m_.scenes[s].nodes;
    } else {
      for (std::size_t i = 0; i < m_.nodes.size(); ++i)
        if (parent[i] < 0) roots.push_back(int(i));
    }
    for (int r : roots)
      if (r < 0 || std::size_t(r) >= m_.nodes.size())
        throw MeshError(source_, "scene names node " + std::to_string(r) + ", which does not exist");
    return roots;
  }

  // Whether `node` or a node below it has a mesh. Iterative, each node looked at once: a corrupt
  // graph (shared children, cycles, a very deep chain) is refused later by visit(), not here.
  bool has_mesh(int node) const {
    std::vector<char> seen(m_.nodes.size(), 0);
    std::vector<int> todo = {node};
    while (!todo.empty()) {
      const int i = todo.back();
      todo.pop_back();
      if (i < 0 || std::size_t(i) >= m_.nodes.size() || seen[std::size_t(i)]) continue;
      seen[std::size_t(i)] = 1;
      const tinygltf::Node& n = m_.nodes[std::size_t(i)];
      if (n.mesh >= 0) return true;
      todo.insert(todo.end(), n.children.begin(), n.children.end());
    }
    return false;
  }

  // The nodes to import and their parents' world transforms.
  std::vector<std::pair<int, Mat4>> roots() {
    const std::vector<int> parent = parents();
    const std::vector<int> scene = scene_roots(parent);
    const std::set<int> in_scene(scene.begin(), scene.end());
    for (int r : scene)
      if (parent[std::size_t(r)] >= 0)
        warn("scene root " + node_label(m_, r) + " is a child of " + node_label(m_, parent[std::size_t(r)]) +
             ", which the scene does not list: imported as a root, without that node's transform");
    if (!options_.node.empty()) {
      for (std::size_t i = 0; i < m_.nodes.size(); ++i) {
        if (m_.nodes[i].name != options_.node) continue;
        Mat4 world = Mat4::Identity();
        std::size_t steps = 0;
        for (int a = int(i); !in_scene.count(a) && parent[std::size_t(a)] >= 0 && steps <= m_.nodes.size();
             ++steps) {
          a = parent[std::size_t(a)];
          world = local_matrix(m_.nodes[std::size_t(a)]) * world;
        }
        return {{int(i), world}};
      }
      std::vector<std::string> names;
      for (const tinygltf::Node& n : m_.nodes)
        if (!n.name.empty()) names.push_back("'" + n.name + "'");
      std::string list;
      for (std::size_t i = 0; i < names.size() && i < 20; ++i) list += (i ? ", " : "") + names[i];
      if (names.size() > 20) list += " and " + std::to_string(names.size() - 20) + " more";
      throw MeshError(source_, "no node is named '" + options_.node + "'" +
                                   (names.empty() ? std::string(" (the file names no nodes)")
                                                  : "; the nodes are " + list));
    }
    std::vector<std::pair<int, Mat4>> out;
    std::string with_geometry;
    std::size_t count = 0;
    for (int r : scene) {
      out.emplace_back(r, Mat4::Identity());
      if (has_mesh(r)) with_geometry += std::string(count++ ? ", " : "") + node_label(m_, r);
    }
    if (count > 1)
      warn("the scene has " + std::to_string(count) + " top-level nodes with geometry (" + with_geometry +
           "): imported together as one model; set `node` to import one");
    return out;
  }

  void visit(int index, const Mat4& parent, const std::string& path, std::size_t depth) {
    if (index < 0 || std::size_t(index) >= m_.nodes.size())
      throw MeshError(source_, "node " + std::to_string(index) + " does not exist");
    // glTF 2.0 §3.5.3: the nodes form disjoint trees. A node reached twice (listed as a child
    // twice, under two parents, in a cycle, or in the scene with its ancestor) would be imported
    // twice, or exponentially often; a chain deeper than Assimp's limit would exhaust the stack.
    if (depth > kMaxNodeDepth)
      throw MeshError(source_,
                      "the node hierarchy is deeper than " + std::to_string(kMaxNodeDepth) + " levels");
    if (visited_.empty()) visited_.assign(m_.nodes.size(), 0);
    if (visited_[std::size_t(index)])
      throw MeshError(source_, node_label(m_, index) + " is reached twice (glTF nodes form a tree)");
    visited_[std::size_t(index)] = 1;
    const tinygltf::Node& node = m_.nodes[std::size_t(index)];
    const Mat4 world = parent * local_matrix(node);
    const std::string here =
        path + (path.empty() ? "" : "/") + (node.name.empty() ? "node" + std::to_string(index) : node.name);
    if (node.mesh >= 0) {
      if (std::size_t(node.mesh) >= m_.meshes.size())
        throw MeshError(source_, node_label(m_, index) + " names mesh " + std::to_string(node.mesh) +
                                     ", which does not exist");
      const tinygltf::Mesh& mesh = m_.meshes[std::size_t(node.mesh)];
      const std::string name =
          here + "/" + (mesh.name.empty() ? "mesh" + std::to_string(node.mesh) : mesh.name);
      for (std::size_t i = 0; i < mesh.primitives.size(); ++i) {
        const std::string what = "mesh " + std::to_string(node.mesh) +
                                 (mesh.name.empty() ? "" : " '" + mesh.name + "'") + " primitive " +
                                 std::to_string(i);
        add_primitive(mesh.primitives[i], world, name, what);
      }
    }
    for (int child : node.children) visit(child, world, here, depth + 1);
  }

  void add_primitive(const tinygltf::Primitive& gp, const Mat4& world, const std::string& name,
                     const std::string& what) {
    if (gp.mode != TINYGLTF_MODE_TRIANGLES && gp.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        gp.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      warn(what + " (in '" + name + "'): mode " + std::to_string(gp.mode) +
           " (points or lines) skipped: sylva imports triangles");
      return;
    }
    if (gp.material >= 0 && std::size_t(gp.material) >= m_.materials.size())
      throw MeshError(source_, what + ": material " + std::to_string(gp.material) + " does not exist");
    std::optional<render::detail::DracoData> draco;
    if (auto it = gp.extensions.find(render::detail::kDraco); it != gp.extensions.end())
      draco = render::detail::decode_draco(in_, it->second, what);
    auto fetch = [&](const std::string& attr) -> std::optional<AttributeData> {
      if (draco)
        if (auto d = draco->attributes.find(attr); d != draco->attributes.end()) return d->second;
      auto a = gp.attributes.find(attr);
      if (a == gp.attributes.end()) return std::nullopt;
      return in_.read_accessor(a->second, what + " attribute " + attr);
    };
    // The vertex limit before POSITION is read: its accessor's count sizes every attribute.
    if (auto a = gp.attributes.find("POSITION");
        !draco && a != gp.attributes.end() && a->second >= 0 && std::size_t(a->second) < m_.accessors.size())
      check_mesh_limits(source_, vertices_ + m_.accessors[std::size_t(a->second)].count, triangles_,
                        options_);
    const std::optional<AttributeData> pos = fetch("POSITION");
    if (!pos) throw MeshError(source_, what + ": has no POSITION attribute");
    if (pos->components != 3) throw MeshError(source_, what + ": POSITION must be VEC3");
    const std::size_t n = pos->count;
    check_mesh_limits(source_, vertices_ + n, triangles_, options_);

    tree::SourcePrimitive p;
    p.name = name;
    p.material = gp.material >= 0 ? std::uint32_t(gp.material) : default_material();
    p.positions.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector4d v =
          world * Eigen::Vector4d(pos->values[i * 3], pos->values[i * 3 + 1], pos->values[i * 3 + 2], 1);
      p.positions[i] = tree::Vec3f{float(v.x()), float(v.y()), float(v.z())};
    }
    auto check = [&](const AttributeData& a, const std::string& attr, int comps) {
      if (a.count != n || a.components != comps)
        throw MeshError(source_, what + ": " + attr + " has " + std::to_string(a.count) + " elements of " +
                                     std::to_string(a.components) + " components, POSITION has " +
                                     std::to_string(n));
    };
    const Eigen::Matrix3d normal_matrix = world.topLeftCorner<3, 3>().inverse().transpose();
    if (auto nrm = fetch("NORMAL")) {
      check(*nrm, "NORMAL", 3);
      p.normals.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d v = normal_matrix * Eigen::Vector3d(nrm->values[i * 3], nrm->values[i * 3 + 1],
                                                                  nrm->values[i * 3 + 2]);
        p.normals[i] = tree::Vec3f{float(v.x()), float(v.y()), float(v.z())};
      }
    }
    const render::detail::MaterialUv uv_of =
        gp.material >= 0 ? uv_[std::size_t(gp.material)] : render::detail::MaterialUv{};
    const std::string set = "TEXCOORD_" + std::to_string(uv_of.texcoord_set);
    if (auto uv = fetch(set)) {
      check(*uv, set, 2);
      p.uvs.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        const render::Vec2 t = uv_of.transform.apply(render::Vec2(uv->values[i * 2], uv->values[i * 2 + 1]));
        p.uvs[i] = {t.x(), t.y()};
      }
    }
    std::vector<std::uint32_t> raw;
    if (draco && draco->has_faces) {
      raw = draco->indices;
    } else if (gp.indices >= 0) {
      if (std::size_t(gp.indices) >= m_.accessors.size())
        throw MeshError(source_, what + ": indices accessor does not exist");
      raw = in_.read_indices(gp.indices, what + " indices");
    } else {
      raw.resize(n);
      for (std::size_t i = 0; i < n; ++i) raw[i] = std::uint32_t(i);
    }
    for (std::uint32_t i : raw)
      if (i >= n)
        throw MeshError(source_, what + ": index " + std::to_string(i) + " out of range (" +
                                     std::to_string(n) + " vertices)");
    p.indices = expand(draco && draco->has_faces ? TINYGLTF_MODE_TRIANGLES : gp.mode, raw);
    if (world.topLeftCorner<3, 3>().determinant() < 0)
      for (std::size_t t = 0; t + 2 < p.indices.size(); t += 3) std::swap(p.indices[t + 1], p.indices[t + 2]);
    vertices_ += n;
    triangles_ += p.indices.size() / 3;
    check_mesh_limits(source_, vertices_, triangles_, options_);
    out_.geometry.primitives.push_back(std::move(p));
  }

  const tinygltf::Model& m_;
  GltfModel in_;
  std::string_view source_;
  const SidecarFiles& files_;
  const MeshOptions& options_;
  MeshImport& out_;
  std::vector<render::detail::MaterialUv> uv_;  // per glTF material
  std::map<int, int> image_slot_;               // glTF image -> SourceGeometry image (-1: none)
  std::vector<char> visited_;                   // per glTF node: already imported
  int default_material_ = -1;
  std::size_t vertices_ = 0, triangles_ = 0;
};

}  // namespace

MeshImport read_gltf(std::string bytes, std::string_view source, const SidecarFiles& files,
                     const MeshOptions& options) {
  if (bytes.size() > kMaxMeshFileBytes)
    throw MeshError(source, "file is larger than the import's limit of 256 MiB");
  const tinygltf::Model model = parse(std::move(bytes), source, files);
  MeshImport out;
  out.facts.format = "gltf";
  try {
    Reader(model, source, files, options, out).read();
  } catch (const render::SceneLoadError& e) {
    throw MeshError(std::string(e.what()));
  } catch (const std::bad_alloc&) {
    throw MeshError(source, "out of memory while reading (corrupt counts or a very large asset)");
  } catch (const std::length_error&) {
    throw MeshError(source, "out of memory while reading (corrupt counts or a very large asset)");
  }
  return out;
}

}  // namespace sylva::import
