// Invariant checks for an imported mesh (source_geometry.h states them). The messages name the
// element by index and, when it is short enough to print, by the name the user's file gave it,
// so a user can find the offending node in their modelling tool. The full list of messages is
// in docs/tree-format.md ("Source geometry").
#include "libs/tree/source_geometry.h"

#include <cmath>
#include <string>

#include "libs/tree/tree.h"

namespace sylva::tree {

namespace {

// The first `max` problems found; later ones are dropped and the checks stop early, so a mesh
// of millions of bad indices costs at most one pass.
struct Problems {
  std::vector<std::string> list;
  std::size_t max;
  void fail(std::string msg) {
    if (list.size() < max) list.push_back(std::move(msg));
  }
  bool full() const { return list.size() >= max; }
};

std::string n(std::size_t v) { return std::to_string(v); }

// `source primitive 3 ("lf_12"): `; a name over the stored limit is left out (it is reported
// on its own and would make every message 64 KiB long).
std::string where(const char* what, std::size_t i, const std::string& name) {
  std::string w = std::string("source ") + what + " " + n(i);
  if (name.size() <= kMaxTextBytes) w += " (\"" + name + "\")";
  return w + ": ";
}

void check_name(const std::string& w, const std::string& name, Problems& e) {
  if (name.size() > kMaxTextBytes)
    e.fail(w + "the name is " + n(name.size()) + " bytes, at most " + n(kMaxTextBytes) + " are stored");
}

bool finite2(const std::array<float, 2>& uv) { return std::isfinite(uv[0]) && std::isfinite(uv[1]); }

void check_vertices(const SourcePrimitive& p, const std::string& w, Problems& e) {
  const std::size_t np = p.positions.size();
  if (!p.normals.empty() && p.normals.size() != np)
    e.fail(w + n(p.normals.size()) + " normals for " + n(np) + " positions");
  if (!p.uvs.empty() && p.uvs.size() != np) e.fail(w + n(p.uvs.size()) + " uvs for " + n(np) + " positions");
  for (std::size_t k = 0; k < np && !e.full(); ++k)
    if (!is_finite(p.positions[k])) e.fail(w + "position " + n(k) + " is not finite");
  for (std::size_t k = 0; k < p.normals.size() && !e.full(); ++k) {
    if (!is_finite(p.normals[k]))
      e.fail(w + "normal " + n(k) + " is not finite");
    else if (std::abs(length(to_double(p.normals[k])) - 1.0) > 1e-3)
      e.fail(w + "normal " + n(k) + " is not unit length");
  }
  for (std::size_t k = 0; k < p.uvs.size() && !e.full(); ++k)
    if (!finite2(p.uvs[k])) e.fail(w + "uv " + n(k) + " is not finite");
}

void check_primitive(const SourceGeometry& g, std::size_t i, Problems& e) {
  const SourcePrimitive& p = g.primitives[i];
  const std::string w = where("primitive", i, p.name);
  check_name(w, p.name, e);
  if (p.material >= g.materials.size())
    e.fail(w + "material " + n(p.material) + " is not below " + n(g.materials.size()) + " materials");
  if (p.indices.size() % 3 != 0) e.fail(w + "has " + n(p.indices.size()) + " indices, not a multiple of 3");
  for (std::size_t k = 0; k < p.indices.size() && !e.full(); ++k)
    if (p.indices[k] >= p.positions.size())
      e.fail(w + "index " + n(p.indices[k]) + " at triangle " + n(k / 3) + " is not below " +
             n(p.positions.size()) + " positions");
  check_vertices(p, w, e);
}

void check_material(const SourceGeometry& g, std::size_t i, Problems& e) {
  const SourceMaterial& m = g.materials[i];
  const std::string w = where("material", i, m.name);
  check_name(w, m.name, e);
  auto in01 = [](float v) { return v >= 0 && v <= 1; };  // NaN fails
  if (!in01(m.base_color[0]) || !in01(m.base_color[1]) || !in01(m.base_color[2]) || !in01(m.base_color[3]))
    e.fail(w + "base colour components must be in [0, 1]");
  if (static_cast<unsigned>(m.alpha_mode) > 2)
    e.fail(w + "unknown alpha mode " + n(static_cast<unsigned>(m.alpha_mode)));
  if (!in01(m.alpha_cutoff)) e.fail(w + "alpha cutoff must be in [0, 1]");
  if (m.base_color_image < -1 ||
      (m.base_color_image >= 0 && std::size_t(m.base_color_image) >= g.images.size()))
    e.fail(w + "base colour image " + std::to_string(m.base_color_image) + " is not -1 or below " +
           n(g.images.size()) + " images");
}

void check_image(const SourceGeometry& g, std::size_t i, Problems& e) {
  const SourceImage& im = g.images[i];
  const std::string w = where("image", i, im.name);
  check_name(w, im.name, e);
  if (im.mime_type != "image/png" && im.mime_type != "image/jpeg")
    e.fail(w + "mime type \"" + im.mime_type.substr(0, 64) + "\" is not image/png or image/jpeg");
  if (im.bytes.empty()) e.fail(w + "has no bytes");
}

}  // namespace

std::vector<std::string> validate_source_geometry(const SourceGeometry& g, std::size_t max_errors) {
  Problems e{{}, max_errors};
  // Totals first: past them a file is refused whatever else holds.
  std::size_t vertices = 0, triangles = 0;
  for (const SourcePrimitive& p : g.primitives) {
    vertices += p.positions.size();
    triangles += p.indices.size() / 3;
  }
  if (vertices > kMaxSourceVertices)
    e.fail("source geometry: " + n(vertices) + " vertices, at most " + n(kMaxSourceVertices));
  if (triangles > kMaxSourceTriangles)
    e.fail("source geometry: " + n(triangles) + " triangles, at most " + n(kMaxSourceTriangles));
  for (std::size_t i = 0; i < g.primitives.size() && !e.full(); ++i) check_primitive(g, i, e);
  for (std::size_t i = 0; i < g.materials.size() && !e.full(); ++i) check_material(g, i, e);
  for (std::size_t i = 0; i < g.images.size() && !e.full(); ++i) check_image(g, i, e);
  return std::move(e.list);
}

}  // namespace sylva::tree
