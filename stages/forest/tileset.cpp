// 3D Tiles 1.1 tileset writer (see tileset.h for the error model and the structure).
#include "stages/forest/tileset.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <numbers>

#include "libs/lodmodel/lod_model.h"

namespace sylva::forest {

namespace {

// The geometricError of a tile drawing level `l` of species `s`: its epsilon, except for the
// impostor, whose recorded switch distance d may be a proven one nearer than its error model's
// (impostor.json "switch_distance_m"): the error that distance stands for, d delta s(1)
// (lodmodel::spatial_error), so a client with maximumScreenSpaceError = delta switches to the
// impostor exactly where sylva's views do. For a mesh level d = epsilon / (delta s(1)): the same.
double tile_error(const Species& s, const Level& l) {
  if (!l.impostor || !(l.switch_distance_m > 0)) return l.epsilon_m;
  return lodmodel::spatial_error(lodmodel::camera_from_degrees(s.fov_y_deg, s.height_px), l.switch_distance_m,
                                 s.pixel_error_px);
}

using nlohmann::json;

// 3D Tiles box: centre and three half-axis vectors, in the tileset's Z-up frame.
json box_volume(const Box3& b) {
  const double cx = 0.5 * (b.min[0] + b.max[0]), cy = 0.5 * (b.min[1] + b.max[1]),
               cz = 0.5 * (b.min[2] + b.max[2]);
  const double hx = std::max(0.5 * (b.max[0] - b.min[0]), 1e-3),
               hy = std::max(0.5 * (b.max[1] - b.min[1]), 1e-3),
               hz = std::max(0.5 * (b.max[2] - b.min[2]), 1e-3);
  // glTF (x, y, z) -> tileset (x, -z, y).
  return {{"box", {cx, -cz, cy, hx, 0, 0, 0, hz, 0, 0, 0, hy}}};
}

Box3 merge(const Box3& a, const Box3& b) {
  Box3 o;
  for (std::size_t k = 0; k < 3; ++k) {
    o.min[k] = std::min(a.min[k], b.min[k]);
    o.max[k] = std::max(a.max[k], b.max[k]);
  }
  return o;
}

}  // namespace

std::array<double, 16> enu_to_ecef(const Georeference& g) {
  constexpr double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  const double lon = g.longitude_deg * std::numbers::pi / 180, lat = g.latitude_deg * std::numbers::pi / 180;
  const double sl = std::sin(lon), cl = std::cos(lon), sp = std::sin(lat), cp = std::cos(lat);
  const double n = a / std::sqrt(1 - e2 * sp * sp);
  const double px = (n + g.height_m) * cp * cl, py = (n + g.height_m) * cp * sl,
               pz = (n * (1 - e2) + g.height_m) * sp;
  return {-sl, cl, 0, 0, -sp * cl, -sp * sl, cp, 0, cp * cl, cp * sl, sp, 0, px, py, pz, 1};
}

std::size_t species_level(const Species& s, int tile_level, int level_count) {
  const std::size_t last = s.levels.size() - 1;
  if (tile_level >= level_count - 1) return last;
  const std::size_t lods = s.levels.back().impostor && last > 0 ? last : last + 1;
  return std::min<std::size_t>(std::size_t(std::max(tile_level, 0)), lods - 1);
}

namespace {

using ContentUri = std::function<std::string(std::size_t, int)>;

// The error of drawing none of a subtree's trees: the tallest tree's height (at least 1 m).
double empty_error_of(const Forest& forest) {
  double empty_error = 0;
  for (const Instance& in : forest.instances) {
    const Species& s = forest.species[in.species];
    empty_error = std::max(empty_error, (s.bounds.max[1] - s.bounds.min[1]) * in.scale[1]);
  }
  return std::max(empty_error, 1.0);
}

// The error of drawing tile t's trees at tile level `level`: the largest of its species' levels.
double level_error(const Forest& forest, const Tile& t, int level, int level_count) {
  double e = 0;
  for (std::uint32_t i : t.instances) {
    const Species& s = forest.species[forest.instances[i].species];
    e = std::max(e, tile_error(s, s.levels[species_level(s, level, level_count)]));
  }
  return e;
}

// Tile t's chain: one node per level, the coarsest outermost, each the parent of the next finer
// (REPLACE refinement), with non-decreasing errors from the finest level up.
json tile_chain(const Forest& forest, std::size_t t, int level_count, const ContentUri& content_uri) {
  const Tile& tile = forest.tiles[t];
  json node;
  double error = 0;  // non-decreasing from the finest level up
  for (int level = 0; level < level_count; ++level) {
    error = std::max(error, level_error(forest, tile, level, level_count));
    json n = {{"boundingVolume", box_volume(tile.bounds)},
              {"geometricError", error},
              {"refine", "REPLACE"},
              {"content", {{"uri", content_uri(t, level)}}}};
    if (level > 0) n["children"] = json::array({std::move(node)});
    node = std::move(n);
  }
  return node;
}

// Quadtree over the tile grid: split the index rectangle until one tile is left.
struct TileQuadtree {
  const Forest& forest;
  int level_count;
  const ContentUri& content_uri;
  double empty_error;

  // The subtree over tile indices [x0, x1) x [z0, z1): `any` tells whether it holds a tile,
  // `bounds` receives its box (when it does).
  json build(int x0, int z0, int x1, int z1, Box3& bounds, bool& any) const {
    std::vector<std::size_t> inside;
    for (std::size_t t = 0; t < forest.tiles.size(); ++t) {
      const Tile& tile = forest.tiles[t];
      if (tile.ix >= x0 && tile.ix < x1 && tile.iz >= z0 && tile.iz < z1) inside.push_back(t);
    }
    any = !inside.empty();
    if (!any) return {};
    if (x1 - x0 <= 1 && z1 - z0 <= 1) {  // one grid cell: one tile
      bounds = forest.tiles[inside[0]].bounds;
      return tile_chain(forest, inside[0], level_count, content_uri);
    }
    const int mx = x1 - x0 > 1 ? (x0 + x1) / 2 : x1, mz = z1 - z0 > 1 ? (z0 + z1) / 2 : z1;
    json children = json::array();
    bool first = true;
    const int xs[3] = {x0, mx, x1}, zs[3] = {z0, mz, z1};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        if (xs[a] >= xs[a + 1] || zs[b] >= zs[b + 1]) continue;
        Box3 cb;
        bool cany = false;
        json c = build(xs[a], zs[b], xs[a + 1], zs[b + 1], cb, cany);
        if (!cany) continue;
        bounds = first ? cb : merge(bounds, cb);
        first = false;
        children.push_back(std::move(c));
      }
    if (children.size() == 1) return std::move(children[0]);
    return {{"boundingVolume", box_volume(bounds)},
            {"geometricError", empty_error},
            {"refine", "REPLACE"},
            {"children", std::move(children)}};
  }
};

}  // namespace

std::string tileset_json(const Forest& forest, int level_count, const Georeference& geo,
                         const ContentUri& content_uri, const Box3& ground_bounds) {
  const double empty_error = empty_error_of(forest);
  int x0 = 0, z0 = 0, x1 = 1, z1 = 1;
  for (const Tile& t : forest.tiles) {
    x0 = std::min(x0, t.ix);
    z0 = std::min(z0, t.iz);
    x1 = std::max(x1, t.ix + 1);
    z1 = std::max(z1, t.iz + 1);
  }
  Box3 bounds;
  bool any = false;
  json root = TileQuadtree{forest, level_count, content_uri, empty_error}.build(x0, z0, x1, z1, bounds, any);
  if (!any) {
    Box3 b{{forest.extent_min[0], 0, forest.extent_min[1]}, {forest.extent_max[0], 1, forest.extent_max[1]}};
    root = {{"boundingVolume", box_volume(b)}, {"geometricError", 0.0}, {"refine", "REPLACE"}};
  }
  // The root is always a content-less node with the transform, so a single-tile forest keeps its chain below
  // it.
  if (root.contains("content")) {
    root = {{"boundingVolume", root["boundingVolume"]},
            {"geometricError", empty_error},
            {"refine", "REPLACE"},
            {"children", json::array({root})}};
  }
  if (!forest.ground.empty()) {
    if (!root.contains("children")) root["children"] = json::array();
    root["children"].push_back({{"boundingVolume", box_volume(ground_bounds)},
                                {"geometricError", 0.0},
                                {"content", {{"uri", forest.ground}}}});
    root["boundingVolume"] = box_volume(any ? merge(bounds, ground_bounds) : ground_bounds);
  }
  const auto m = enu_to_ecef(geo);
  root["transform"] = json(std::vector<double>(m.begin(), m.end()));
  json ts;
  ts["asset"] = {{"version", "1.1"}, {"generator", "sylva"}};
  ts["geometricError"] = empty_error;
  ts["root"] = std::move(root);
  return ts.dump(1) + "\n";
}

}  // namespace sylva::forest
