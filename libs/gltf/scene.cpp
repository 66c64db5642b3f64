// validate_scene(): the contract of scene.h, checked before anything is written so that every
// problem is reported with the element it concerns instead of surfacing as a validator error.
#include "libs/gltf/scene.h"

#include <cmath>
#include <set>
#include <string>

namespace sylva::gltf {
namespace {

// Tolerance on unit lengths. The Khronos validator accepts |len - 1| up to about 5e-4; 1e-4
// leaves room for float rounding in consumers that renormalise.
constexpr double kUnitTolerance = 1e-4;

class Checker {
 public:
  explicit Checker(std::size_t max) : max_(max) {}

  bool full() const { return errors_.size() >= max_; }
  void fail(const std::string& where, const std::string& what) {
    if (!full()) errors_.push_back(where + ": " + what);
  }
  std::vector<std::string> take() { return std::move(errors_); }

 private:
  std::size_t max_;
  std::vector<std::string> errors_;
};

bool all_finite(const std::vector<float>& v) {
  for (float x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// `values` holds `components` floats per vertex for `vertices` vertices.
bool check_size(Checker& c, const std::string& where, const char* name, const std::vector<float>& values,
                std::size_t components, std::size_t vertices) {
  if (values.empty()) return false;
  if (values.size() != components * vertices) {
    c.fail(where, std::string(name) + " has " + std::to_string(values.size()) + " values, expected " +
                      std::to_string(components) + " per vertex (" + std::to_string(components * vertices) +
                      ")");
    return false;
  }
  if (!all_finite(values)) {
    c.fail(where, std::string(name) + " contains a value that is not finite");
    return false;
  }
  return true;
}

void check_unit(Checker& c, const std::string& where, const char* name, const std::vector<float>& v,
                std::size_t stride) {
  for (std::size_t i = 0; i + 2 < v.size(); i += stride) {
    const double len =
        std::sqrt(double(v[i]) * v[i] + double(v[i + 1]) * v[i + 1] + double(v[i + 2]) * v[i + 2]);
    if (std::abs(len - 1.0) > kUnitTolerance) {
      c.fail(where, std::string(name) + " of vertex " + std::to_string(i / stride) + " has length " +
                        std::to_string(len) + ", expected 1");
      return;
    }
  }
}

void check_primitive(Checker& c, const Scene& s, const Primitive& p, const std::string& where) {
  if (p.positions.empty() || p.positions.size() % 3 != 0) {
    c.fail(where, "positions has " + std::to_string(p.positions.size()) +
                      " values; expected a non-zero multiple of 3");
    return;
  }
  const std::size_t n = p.vertex_count();
  if (!all_finite(p.positions)) c.fail(where, "positions contains a value that is not finite");
  if (check_size(c, where, "normals", p.normals, 3, n)) check_unit(c, where, "normal", p.normals, 3);
  if (check_size(c, where, "tangents", p.tangents, 4, n)) {
    if (p.normals.empty()) c.fail(where, "tangents need normals");
    check_unit(c, where, "tangent", p.tangents, 4);
    for (std::size_t i = 3; i < p.tangents.size(); i += 4)
      if (p.tangents[i] != 1.0f && p.tangents[i] != -1.0f) {
        c.fail(where, "tangent w of vertex " + std::to_string(i / 4) + " is not +1 or -1");
        break;
      }
  }
  check_size(c, where, "texcoords", p.texcoords, 2, n);
  if (check_size(c, where, "colors", p.colors, 4, n)) {
    for (float x : p.colors)
      if (x < 0.0f || x > 1.0f) {
        c.fail(where, "colors has a value outside [0, 1]");
        break;
      }
  }
  std::set<std::string> names;
  for (const CustomAttribute& a : p.custom) {
    if (a.name.size() < 2 || a.name[0] != '_')
      c.fail(where, "custom attribute '" + a.name + "' must start with '_'");
    if (!names.insert(a.name).second) c.fail(where, "custom attribute '" + a.name + "' appears twice");
    if (a.components < 1 || a.components > 4) {
      c.fail(where, "custom attribute '" + a.name + "' has " + std::to_string(a.components) + " components");
      continue;
    }
    if (a.values.empty()) {
      c.fail(where, "custom attribute '" + a.name + "' has no values");
      continue;
    }
    check_size(c, where, ("custom attribute '" + a.name + "'").c_str(), a.values, std::size_t(a.components),
               n);
  }
  const std::size_t per = p.mode == PrimitiveMode::kTriangles ? 3 : p.mode == PrimitiveMode::kLines ? 2 : 1;
  const std::size_t elements = p.indices.empty() ? n : p.indices.size();
  if (elements % per != 0 || elements == 0)
    c.fail(where, std::string(p.indices.empty() ? "vertex" : "index") + " count " + std::to_string(elements) +
                      " does not fit the mode (a non-zero multiple of " + std::to_string(per) + ")");
  for (std::size_t i = 0; i < p.indices.size(); ++i)
    if (p.indices[i] >= n) {
      c.fail(where, "index " + std::to_string(i) + " is " + std::to_string(p.indices[i]) +
                        ", but there are " + std::to_string(n) + " vertices");
      break;
    }
  if (p.buffer < -1 || (p.buffer > 0 && p.buffer >= static_cast<int>(s.buffer_uris.size())))
    c.fail(where, "buffer " + std::to_string(p.buffer) + " is not in buffer_uris");
  if (p.material < -1 || p.material >= static_cast<int>(s.materials.size()))
    c.fail(where, "material " + std::to_string(p.material) + " does not exist");
  if (!p.extras.is_null() && !p.extras.is_object()) c.fail(where, "extras must be a JSON object");
}

bool unit_interval(float x) { return x >= 0.0f && x <= 1.0f; }

// A file name that is also a relative URI needing no escaping, with no directory part.
bool plain_file_name(const std::string& n) {
  if (n.empty() || n == "." || n == "..") return false;
  for (char ch : n)
    if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '.' ||
          ch == '_' || ch == '-'))
      return false;
  return true;
}

// Images: bytes, a supported mime type, and a plain file name as uri; no uri (image or buffer)
// used twice.
void check_images(Checker& c, const Scene& s) {
  for (std::size_t i = 0; i < s.images.size() && !c.full(); ++i) {
    const Image& im = s.images[i];
    const std::string where = "images[" + std::to_string(i) + "]";
    if (im.bytes.empty()) c.fail(where, "has no bytes");
    if (im.mime_type != "image/png" && im.mime_type != "image/jpeg")
      c.fail(where, "mime type '" + im.mime_type + "' is not image/png or image/jpeg");
    if (!im.uri.empty() && !plain_file_name(im.uri))
      c.fail(where, "uri '" + im.uri + "' is not a plain file name (letters, digits, '.', '_', '-')");
  }
  std::set<std::string> uris;
  for (const Image& im : s.images)
    if (!im.uri.empty() && !uris.insert(im.uri).second)
      c.fail("images", "uri '" + im.uri + "' is used twice");
  for (std::size_t b = 0; b < s.buffer_uris.size(); ++b) {
    const std::string& u = s.buffer_uris[b];
    if (!plain_file_name(u))
      c.fail("buffer_uris[" + std::to_string(b) + "]", "'" + u + "' is not a plain file name");
    if (!uris.insert(u).second) c.fail("buffer_uris[" + std::to_string(b) + "]", "'" + u + "' is used twice");
  }
}

void check_materials(Checker& c, const Scene& s) {
  for (std::size_t i = 0; i < s.materials.size() && !c.full(); ++i) {
    const Material& m = s.materials[i];
    const std::string where = "materials[" + std::to_string(i) + "]";
    for (float x : m.base_color)
      if (!unit_interval(x)) c.fail(where, "base_color has a value outside [0, 1]");
    if (!unit_interval(m.metallic) || !unit_interval(m.roughness))
      c.fail(where, "metallic/roughness outside [0, 1]");
    if (!(m.alpha_cutoff >= 0.0f)) c.fail(where, "alpha_cutoff must be >= 0");
    for (const int t : {m.base_color_texture.image, m.normal_texture.image})
      if (t < -1 || t >= static_cast<int>(s.images.size()))
        c.fail(where, "texture image " + std::to_string(t) + " does not exist");
    if (!m.extras.is_null() && !m.extras.is_object()) c.fail(where, "extras must be a JSON object");
  }
}

void check_meshes(Checker& c, const Scene& s) {
  for (std::size_t i = 0; i < s.meshes.size() && !c.full(); ++i) {
    const Mesh& m = s.meshes[i];
    const std::string where = "meshes[" + std::to_string(i) + "]";
    if (m.primitives.empty()) c.fail(where, "has no primitives");
    if (m.buffer < 0 || (m.buffer > 0 && m.buffer >= static_cast<int>(s.buffer_uris.size())))
      c.fail(where, "buffer " + std::to_string(m.buffer) + " is not in buffer_uris");
    for (std::size_t j = 0; j < m.primitives.size() && !c.full(); ++j)
      check_primitive(c, s, m.primitives[j], where + ".primitives[" + std::to_string(j) + "]");
    if (!m.extras.is_null() && !m.extras.is_object()) c.fail(where, "extras must be a JSON object");
  }
}

// A node's instances: a mesh to instance, arrays of whole finite values that agree on the
// instance count, unit rotations.
void check_instances(Checker& c, const Node& n, const std::string& where) {
  const Instances& in = n.instances;
  if (n.mesh < 0) c.fail(where, "instances need a mesh");
  std::size_t count = 0;
  auto per_instance = [&](const std::vector<float>& v, std::size_t comps, const char* name) {
    if (v.empty()) return;
    if (v.size() % comps != 0 || !all_finite(v)) {
      c.fail(where, std::string("instance ") + name + " must hold " + std::to_string(comps) +
                        " finite values per instance");
      return;
    }
    const std::size_t k = v.size() / comps;
    if (count != 0 && k != count) c.fail(where, "instance arrays disagree on the instance count");
    count = k;
  };
  per_instance(in.translations, 3, "translations");
  per_instance(in.rotations, 4, "rotations");
  per_instance(in.scales, 3, "scales");
  for (std::size_t k = 0; k + 3 < in.rotations.size(); k += 4) {
    const double l = std::sqrt(double(in.rotations[k]) * in.rotations[k] +
                               double(in.rotations[k + 1]) * in.rotations[k + 1] +
                               double(in.rotations[k + 2]) * in.rotations[k + 2] +
                               double(in.rotations[k + 3]) * in.rotations[k + 3]);
    if (std::abs(l - 1.0) > kUnitTolerance) {
      c.fail(where, "instance rotation " + std::to_string(k / 4) + " is not a unit quaternion");
      break;
    }
  }
}

// Node i: its mesh exists, its children are other nodes (counted into `parents`), its
// transform is finite with a unit rotation, its instances and JSON members are well formed.
void check_node(Checker& c, const Scene& s, int i, std::vector<int>& parents) {
  const int node_count = static_cast<int>(s.nodes.size());
  const Node& n = s.nodes[static_cast<std::size_t>(i)];
  const std::string where = "nodes[" + std::to_string(i) + "]";
  if (n.mesh < -1 || n.mesh >= static_cast<int>(s.meshes.size()))
    c.fail(where, "mesh " + std::to_string(n.mesh) + " does not exist");
  for (int ch : n.children) {
    if (ch < 0 || ch >= node_count || ch == i) {
      c.fail(where, "child " + std::to_string(ch) + " is not another node");
    } else {
      ++parents[static_cast<std::size_t>(ch)];
    }
  }
  const auto& q = n.rotation;
  const double qlen = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(qlen - 1.0) > kUnitTolerance) c.fail(where, "rotation is not a unit quaternion");
  for (double x : n.translation)
    if (!std::isfinite(x)) c.fail(where, "translation is not finite");
  for (double x : n.scale)
    if (!std::isfinite(x)) c.fail(where, "scale is not finite");
  if (!n.instances.empty()) check_instances(c, n, where);
  if (!n.extras.is_null() && !n.extras.is_object()) c.fail(where, "extras must be a JSON object");
  if (!n.extensions.is_null() && !n.extensions.is_object()) c.fail(where, "extensions must be a JSON object");
  if (n.extensions.is_object() && n.extensions.contains("EXT_mesh_gpu_instancing"))
    c.fail(where, "EXT_mesh_gpu_instancing is written from `instances`, not `extensions`");
}

// Roots exist, have no parent and are listed once.
void check_roots(Checker& c, const Scene& s, const std::vector<int>& parents) {
  const int node_count = static_cast<int>(s.nodes.size());
  std::vector<char> is_root(s.nodes.size(), 0);
  for (int r : s.roots) {
    if (r < 0 || r >= node_count) {
      c.fail("roots", "node " + std::to_string(r) + " does not exist");
    } else if (parents[static_cast<std::size_t>(r)] != 0) {
      c.fail("roots", "node " + std::to_string(r) + " is a child of another node");
    } else if (is_root[static_cast<std::size_t>(r)]++) {
      c.fail("roots", "node " + std::to_string(r) + " is listed twice");
    }
  }
}

// Cycles: with at most one parent each, a node is on a cycle iff no walk down from a
// parent-less node reaches it. Reports the first such node.
void check_cycles(Checker& c, const Scene& s, const std::vector<int>& parents) {
  const int node_count = static_cast<int>(s.nodes.size());
  std::vector<char> reached(s.nodes.size(), 0);
  std::vector<int> stack;
  for (int i = 0; i < node_count; ++i)
    if (parents[static_cast<std::size_t>(i)] == 0) stack.push_back(i);
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    if (reached[static_cast<std::size_t>(i)]++) continue;
    for (int ch : s.nodes[static_cast<std::size_t>(i)].children)
      if (ch >= 0 && ch < node_count) stack.push_back(ch);
  }
  for (int i = 0; i < node_count; ++i)
    if (!reached[static_cast<std::size_t>(i)]) {
      c.fail("nodes[" + std::to_string(i) + "]", "is part of a cycle");
      break;
    }
}

}  // namespace

std::vector<std::string> validate_scene(const Scene& s, std::size_t max_errors) {
  Checker c(max_errors);
  check_images(c, s);
  check_materials(c, s);
  check_meshes(c, s);
  // Nodes: indices in range, every node has at most one parent, no cycles.
  const int node_count = static_cast<int>(s.nodes.size());
  std::vector<int> parents(s.nodes.size(), 0);
  for (int i = 0; i < node_count && !c.full(); ++i) check_node(c, s, i, parents);
  for (int i = 0; i < node_count; ++i)
    if (parents[static_cast<std::size_t>(i)] > 1)
      c.fail("nodes[" + std::to_string(i) + "]", "has more than one parent");
  check_roots(c, s, parents);
  check_cycles(c, s, parents);
  if (!s.extras.is_null() && !s.extras.is_object()) c.fail("scene", "extras must be a JSON object");
  return c.take();
}

}  // namespace sylva::gltf
