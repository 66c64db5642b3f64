// Axes, units and the trunk foot (mesh_frame.h). Computed in double so a 100 m placement in
// the file does not cost the small model its precision; stored back as float.
#include "stages/import/mesh_frame.h"

#include <algorithm>
#include <limits>

namespace sylva::import {

void to_sylva_frame(tree::SourceGeometry& g, MeshFacts& facts, const MeshOptions& options) {
  const bool z_up = facts.up == 'z';
  const double s = facts.unit_scale * options.scale;
  // 1-2. Axes and units.
  for (tree::SourcePrimitive& p : g.primitives) {
    for (tree::Vec3f& v : p.positions) {
      const double x = v.x, y = z_up ? v.z : v.y, z = z_up ? -double(v.y) : v.z;
      v = tree::Vec3f{float(x * s), float(y * s), float(z * s)};
    }
    if (z_up)
      for (tree::Vec3f& n : p.normals) n = tree::Vec3f{n.x, n.z, -n.y};
  }
  // 3. The foot.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const tree::SourcePrimitive& p : g.primitives)
    for (const tree::Vec3f& v : p.positions) {
      lo = std::min(lo, double(v.y));
      hi = std::max(hi, double(v.y));
    }
  if (!(lo <= hi)) return;  // no vertices
  facts.height = hi - lo;
  if (!options.recenter) return;
  const double band = lo + kFootBand * (hi - lo);
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, z0 = x0, z1 = -x0;
  for (const tree::SourcePrimitive& p : g.primitives)
    for (const tree::Vec3f& v : p.positions)
      if (v.y <= band) {
        x0 = std::min(x0, double(v.x));
        x1 = std::max(x1, double(v.x));
        z0 = std::min(z0, double(v.z));
        z1 = std::max(z1, double(v.z));
      }
  const double cx = 0.5 * (x0 + x1), cz = 0.5 * (z0 + z1);
  for (tree::SourcePrimitive& p : g.primitives)
    for (tree::Vec3f& v : p.positions) v = tree::Vec3f{float(v.x - cx), float(v.y - lo), float(v.z - cz)};
}

}  // namespace sylva::import
