// Tree statistics (definitions in stats.h).
#include "libs/tree/stats.h"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "libs/tree/foliage.h"

namespace sylva::tree {

namespace {

struct Box {
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi = -lo;
  bool empty = true;
  void add(Vec3 p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    empty = false;
  }
};

std::string fmt(double v, int decimals = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// Built by appending (GCC 12 warns falsely, -Wrestrict, on "[" + std::string at -O3).
std::string fmt_vec(Vec3 v, int decimals = 3, const char* sep = ", ") {
  std::string out(1, '[');
  out.append(fmt(v.x, decimals))
      .append(sep)
      .append(fmt(v.y, decimals))
      .append(sep)
      .append(fmt(v.z, decimals));
  out.push_back(']');
  return out;
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

const char* alpha_mode_name(AlphaMode m) {
  switch (m) {
    case AlphaMode::kOpaque:
      return "opaque";
    case AlphaMode::kMask:
      return "mask";
    case AlphaMode::kBlend:
      return "blend";
  }
  return "?";
}

SourceStats source_stats(const SourceGeometry& g) {
  SourceStats s;
  s.primitives = g.primitives.size();
  for (const SourcePrimitive& p : g.primitives) {
    s.vertices += p.positions.size();
    s.triangles += p.indices.size() / 3;
  }
  for (const SourceMaterial& m : g.materials) s.materials.push_back({m.name, m.alpha_mode});
  for (const SourceImage& im : g.images) s.images.push_back({im.name, im.mime_type, im.bytes.size()});
  return s;
}

std::string format_source(const SourceStats& s) {
  std::string out = "source: " + std::to_string(s.primitives) + " primitives, " +
                    std::to_string(s.triangles) + " triangles, " + std::to_string(s.vertices) + " vertices\n";
  for (std::size_t i = 0; i < s.materials.size(); ++i)
    out.append("source material ")
        .append(std::to_string(i))
        .append(": ")
        .append(json_string(s.materials[i].name))
        .append(" (")
        .append(alpha_mode_name(s.materials[i].alpha_mode))
        .append(")\n");
  for (std::size_t i = 0; i < s.images.size(); ++i)
    out.append("source image ")
        .append(std::to_string(i))
        .append(": ")
        .append(json_string(s.images[i].name))
        .append(" (")
        .append(s.images[i].mime_type)
        .append(", ")
        .append(std::to_string(s.images[i].bytes))
        .append(" bytes)\n");
  return out;
}

std::string format_source_json(const SourceStats& s) {
  std::string out = ",\"source\":{\"primitives\":";
  out.append(std::to_string(s.primitives))
      .append(",\"triangles\":")
      .append(std::to_string(s.triangles))
      .append(",\"vertices\":")
      .append(std::to_string(s.vertices))
      .append(",\"materials\":[");
  for (std::size_t i = 0; i < s.materials.size(); ++i)
    out.append(i ? "," : "")
        .append("{\"name\":")
        .append(json_string(s.materials[i].name))
        .append(",\"alpha_mode\":\"")
        .append(alpha_mode_name(s.materials[i].alpha_mode))
        .append("\"}");
  out.append("],\"images\":[");
  for (std::size_t i = 0; i < s.images.size(); ++i)
    out.append(i ? "," : "")
        .append("{\"name\":")
        .append(json_string(s.images[i].name))
        .append(",\"mime_type\":")
        .append(json_string(s.images[i].mime_type))
        .append(",\"bytes\":")
        .append(std::to_string(s.images[i].bytes))
        .append("}");
  return out.append("]}");
}

}  // namespace

TreeStats compute_stats(const Tree& tree) {
  TreeStats s;
  s.name = tree.name;
  s.source = source_stats(tree.source);
  s.branches = tree.branches.size();
  s.leaves = tree.leaves.size();
  s.needles = tree.needles.size();
  Box box;
  for (const Branch& b : tree.branches) {
    if (s.branches_per_level.size() <= b.level) s.branches_per_level.resize(b.level + 1, 0);
    ++s.branches_per_level[b.level];
    s.nodes += b.nodes.size();
    for (std::size_t k = 0; k < b.nodes.size(); ++k) {
      box.add(b.nodes[k].position);
      if (k > 0) s.total_branch_length += length(b.nodes[k].position - b.nodes[k - 1].position);
    }
  }
  for (const Leaf& l : tree.leaves) {
    const Vec3 p = to_double(l.position);
    box.add(p);
    box.add(p + to_double(l.direction) * static_cast<double>(l.length));
  }
  for (const Needle& n : tree.needles) {
    box.add(to_double(n.base));
    box.add(to_double(n.tip));
  }
  const CrownFoliage crown = crown_foliage(tree);
  s.leaf_area = crown.leaf_area;
  s.crown_area = crown.crown_area;
  s.lai = crown.lai();
  if (!box.empty) {
    s.bounds_min = box.lo;
    s.bounds_max = box.hi;
  }
  if (!tree.branches.empty() && !tree.branches.front().nodes.empty()) {
    const std::vector<Node>& trunk = tree.branches.front().nodes;
    const double base = trunk.front().position.y;
    s.height = box.hi.y - base;
    const double target = base + kBreastHeight;
    for (std::size_t k = 0; k + 1 < trunk.size(); ++k) {
      const double y0 = trunk[k].position.y, y1 = trunk[k + 1].position.y;
      if (y0 <= target && y1 >= target && y1 > y0) {
        const double f = (target - y0) / (y1 - y0);
        s.dbh = 2 * (trunk[k].radius + f * (trunk[k + 1].radius - trunk[k].radius));
        s.has_dbh = true;
        break;
      }
    }
  }
  return s;
}

std::string format_stats(const TreeStats& s) {
  std::string out;
  out += "name: " + s.name + "\n";
  out += "branches: " + std::to_string(s.branches) + " (";
  for (std::size_t l = 0; l < s.branches_per_level.size(); ++l)
    out += (l ? ", level " : "level ") + std::to_string(l) + ": " + std::to_string(s.branches_per_level[l]);
  out += ")\n";
  out += "nodes: " + std::to_string(s.nodes) + "\n";
  out += "leaves: " + std::to_string(s.leaves) + "\n";
  out += "needles: " + std::to_string(s.needles) + "\n";
  out += "height: " + fmt(s.height) + " m\n";
  out += "dbh: " + (s.has_dbh ? fmt(s.dbh) + " m" : std::string("n/a (trunk shorter than 1.3 m)")) + "\n";
  out += "total branch length: " + fmt(s.total_branch_length) + " m\n";
  out += "bounds: " + fmt_vec(s.bounds_min) + " .. " + fmt_vec(s.bounds_max) + " m\n";
  out += "leaf area: " + fmt(s.leaf_area) + " m2 (one-sided)\n";
  out += "crown projected area: " + fmt(s.crown_area) + " m2\n";
  out += "leaf area index: " + fmt(s.lai) + "\n";
  if (!s.source.empty()) out += format_source(s.source);
  return out;
}

std::string format_stats_json(const TreeStats& s) {
  // Appends only (GCC 12 warns falsely, -Wrestrict, on literal + std::string at -O3).
  std::string out = "{\"name\":";
  out.append(json_string(s.name));
  out.append(",\"branches\":").append(std::to_string(s.branches)).append(",\"branches_per_level\":[");
  for (std::size_t l = 0; l < s.branches_per_level.size(); ++l) {
    if (l) out.push_back(',');
    out.append(std::to_string(s.branches_per_level[l]));
  }
  out.append("],\"nodes\":").append(std::to_string(s.nodes));
  out.append(",\"leaves\":").append(std::to_string(s.leaves));
  out.append(",\"needles\":").append(std::to_string(s.needles));
  out.append(",\"height_m\":").append(fmt(s.height, 6));
  out.append(",\"dbh_m\":").append(s.has_dbh ? fmt(s.dbh, 6) : std::string("null"));
  out.append(",\"total_branch_length_m\":").append(fmt(s.total_branch_length, 6));
  out.append(",\"bounds_min_m\":").append(fmt_vec(s.bounds_min, 6, ","));
  out.append(",\"bounds_max_m\":").append(fmt_vec(s.bounds_max, 6, ","));
  out.append(",\"leaf_area_m2\":").append(fmt(s.leaf_area, 6));
  out.append(",\"crown_area_m2\":").append(fmt(s.crown_area, 6));
  out.append(",\"lai\":").append(fmt(s.lai, 6));
  if (!s.source.empty()) out.append(format_source_json(s.source));
  return out.append("}");
}

}  // namespace sylva::tree
