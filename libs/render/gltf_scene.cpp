// glTF -> render::Scene. tinygltf parses the file (and decodes PNG/JPEG images with stb, as
// Debian's libtinygltf is built; meshopt-compressed buffers are decoded before, meshopt_decode.h);
// the loader reads materials and textures (gltf_materials.h), turns accessors into typed arrays
// (gltf_model.h), decodes Draco primitives (gltf_draco.h), expands strips and fans, flattens the
// node hierarchy and instancing into world matrices, and checks every index so the GL side
// never reads out of bounds.
#include "libs/render/gltf_scene.h"

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
#include "libs/render/meshopt_decode.h"

namespace sylva::render {
namespace {

using detail::AttributeData;
using detail::kDraco;
using detail::kInstancing;
using detail::kTextureTransform;
using detail::kUnlit;

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

class Loader {
 public:
  Loader(const tinygltf::Model& model, std::string file, std::filesystem::path base_dir,
         const fileio::FileSource& files)
      : in_(model, std::move(file)),
        m_(model),
        file_(in_.file()),
        base_dir_(std::move(base_dir)),
        files_(files) {}

  Scene load() {
    check_extensions();
    detail::check_images(in_, warnings, base_dir_, files_);
    scene_.source = file_;
    scene_.warnings = ignored_extensions();
    uv_ = detail::load_materials(in_, scene_);
    const Mat4 identity = Mat4::Identity();
    for (int root : root_nodes()) visit(root, identity, 0);
    return std::move(scene_);
  }

  std::string warnings;  // tinygltf's warnings, searched for the reason an image is missing

 private:
  [[noreturn]] void fail(const std::string& why) const { in_.fail(why); }

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

  // ---- 2. Primitives -------------------------------------------------------------------------

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

    std::optional<detail::DracoData> draco;
    if (auto it = gp.extensions.find(kDraco); it != gp.extensions.end())
      draco = detail::decode_draco(in_, it->second, what);

    // An attribute from the Draco block if it is there, else from its accessor.
    auto fetch = [&](const std::string& name) -> std::optional<AttributeData> {
      if (draco) {
        if (auto d = draco->attributes.find(name); d != draco->attributes.end()) return d->second;
      }
      auto a = gp.attributes.find(name);
      if (a == gp.attributes.end()) return std::nullopt;
      return in_.read_accessor(a->second, what + " attribute " + name);
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
      const detail::MaterialUv& uv_of = uv_[std::size_t(p.material)];
      const std::string set = "TEXCOORD_" + std::to_string(uv_of.texcoord_set);
      if (auto uv = fetch(set)) {
        check(*uv, set, {2});
        p.texcoords.resize(n);
        const detail::UvTransform& t = uv_of.transform;
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
      raw = in_.read_indices(gp.indices, what + " indices");
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

  // ---- 3. Nodes and instancing ---------------------------------------------------------------

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
      dst = in_.read_accessor(attrs.Get(name).GetNumberAsInt(), what + " instance " + name);
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

  detail::GltfModel in_;
  const tinygltf::Model& m_;
  const std::string& file_;
  std::filesystem::path base_dir_;
  const fileio::FileSource& files_;
  Scene scene_;
  std::vector<detail::MaterialUv> uv_;    // per material: where its base colour texture reads
  std::map<int, std::size_t> mesh_slot_;  // glTF mesh -> Scene::meshes index
};

}  // namespace

Scene load_gltf_scene(const std::filesystem::path& path, const fileio::FileSource& files) {
  std::string bytes;
  try {
    bytes = files.read(path);
  } catch (const fileio::FileReadError& e) {
    throw SceneLoadError(e.what());
  }
  return load_gltf_scene_from_memory(std::move(bytes), path.string(), path.parent_path(), files);
}

Scene load_gltf_scene_from_memory(std::string bytes, const std::string& name,
                                  const std::filesystem::path& base_dir_path,
                                  const fileio::FileSource& files) {
  const std::string& file = name;
  auto fail = [&](const std::string& why) -> SceneLoadError {
    return SceneLoadError(file + ": error: " + why);
  };
  bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (!binary) {
    // EXT_meshopt_compression over external buffers: read as the GLB of the same asset.
    const auto read_uri = [&](const std::string& uri) {
      try {
        return files.read(base_dir_path / detail::decode_uri(uri));
      } catch (const fileio::FileReadError& e) {
        throw std::runtime_error("cannot read buffer '" + uri + "' (" + e.reason() + ")");
      }
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
    detail::patch_glb(bytes);
  } else if (auto patched = detail::without_draco_index_accessors(bytes)) {
    bytes = std::move(*patched);
  }
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) throw fail("file is larger than 4 GiB");

  tinygltf::Model model;
  tinygltf::TinyGLTF reader;
  reader.SetFsCallbacks(gltf::file_callbacks(files));
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

  Loader loader(model, file, base_dir_path, files);
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
