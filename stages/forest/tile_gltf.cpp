// Tile glTF composition (see tile_gltf.h). Instance transform: W = T(p) R_y(yaw) S B with
// B = T_y(ty) R_b (libs/forest/instances.h). glTF instancing draws node * T' R' S' per instance,
// so W is rewritten as T' R' S' with
//     T' = p + (0, s_y ty, 0)       (R_y keeps the y axis; S scales ty)
//     R' = R_y(yaw) R_b
//     S' = R_b^T S R_b              (S R_b = R_b S'),
// which is a scale only when it is diagonal: R_b permutes the axes (multiples of 90 degrees), or
// S is uniform, or R_b is a rotation about y alone. Otherwise glTF instancing cannot hold the tree
// exactly and the stage says so (instances.json keeps the exact transform either way).
#include "stages/forest/tile_gltf.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <optional>
#include <stdexcept>

#include "libs/gltf/json_numbers.h"

namespace sylva::forest {

namespace {

using nlohmann::json;

void put_f32(std::string& out, double d) {
  const auto v = std::bit_cast<std::uint32_t>(static_cast<float>(d));
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((v >> (8 * b)) & 0xffu));
}

std::array<double, 9> rotation3(const std::array<double, 16>& m) {
  return {m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]};  // column-major 3x3
}

// Quaternion (x, y, z, w) of a column-major rotation matrix (Shepperd's method).
std::array<double, 4> quaternion(const std::array<double, 9>& r) {
  auto at = [&](int row, int col) { return r[std::size_t(col * 3 + row)]; };
  const double tr = at(0, 0) + at(1, 1) + at(2, 2);
  std::array<double, 4> q{};
  if (tr > 0) {
    const double s = std::sqrt(tr + 1.0) * 2;
    q = {(at(2, 1) - at(1, 2)) / s, (at(0, 2) - at(2, 0)) / s, (at(1, 0) - at(0, 1)) / s, 0.25 * s};
  } else if (at(0, 0) > at(1, 1) && at(0, 0) > at(2, 2)) {
    const double s = std::sqrt(1.0 + at(0, 0) - at(1, 1) - at(2, 2)) * 2;
    q = {0.25 * s, (at(0, 1) + at(1, 0)) / s, (at(0, 2) + at(2, 0)) / s, (at(2, 1) - at(1, 2)) / s};
  } else if (at(1, 1) > at(2, 2)) {
    const double s = std::sqrt(1.0 + at(1, 1) - at(0, 0) - at(2, 2)) * 2;
    q = {(at(0, 1) + at(1, 0)) / s, 0.25 * s, (at(1, 2) + at(2, 1)) / s, (at(0, 2) - at(2, 0)) / s};
  } else {
    const double s = std::sqrt(1.0 + at(2, 2) - at(0, 0) - at(1, 1)) * 2;
    q = {(at(0, 2) + at(2, 0)) / s, (at(1, 2) + at(2, 1)) / s, 0.25 * s, (at(1, 0) - at(0, 1)) / s};
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q) c /= n;
  if (q[3] < 0)
    for (double& c : q) c = -c;  // one sign per rotation: bytes do not depend on the branch taken
  return q;
}

std::array<double, 9> mul3(const std::array<double, 9>& a, const std::array<double, 9>& b) {
  std::array<double, 9> c{};
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) {
      double s = 0;
      for (int k = 0; k < 3; ++k) s += a[std::size_t(k * 3 + row)] * b[std::size_t(col * 3 + k)];
      c[std::size_t(col * 3 + row)] = s;
    }
  return c;
}

std::array<double, 9> transpose3(const std::array<double, 9>& a) {
  std::array<double, 9> t{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) t[std::size_t(c * 3 + r)] = a[std::size_t(r * 3 + c)];
  return t;
}

struct Trs {
  std::array<double, 3> t;
  std::array<double, 4> r;
  std::array<double, 3> s;
};

Trs instance_trs(const Species& sp, const Instance& in) {
  Species rot_only = sp;
  rot_only.base_translation_y_m = 0;
  const std::array<double, 9> rb = rotation3(base_matrix(rot_only));
  const double c = std::cos(in.yaw_rad), s = std::sin(in.yaw_rad);
  const std::array<double, 9> ry{c, 0, -s, 0, 1, 0, s, 0, c};
  const std::array<double, 9> sm{in.scale[0], 0, 0, 0, in.scale[1], 0, 0, 0, in.scale[2]};
  const std::array<double, 9> sp_ = mul3(transpose3(rb), mul3(sm, rb));
  const double tol = 1e-9 * std::max({in.scale[0], in.scale[1], in.scale[2]});
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row)
      if (row != col && std::abs(sp_[std::size_t(col * 3 + row)]) > tol)
        throw std::invalid_argument(
            "species '" + sp.name +
            "': its base rotation turns the per-axis scale into a shear, which glTF instancing "
            "cannot express; use multiples of 90 degrees, a rotation about y only, or equal "
            "scale ranges on the axes");
  Trs out;
  out.t = {in.position[0], in.position[1] + in.scale[1] * sp.base_translation_y_m, in.position[2]};
  out.r = quaternion(mul3(ry, rb));
  out.s = {sp_[0], sp_[4], sp_[8]};
  return out;
}

json offset_index(const json& v, std::size_t off) { return json(v.get<std::size_t>() + off); }

// TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN (glTF's default mode is TRIANGLES).
bool triangle_mode(const json& primitive) {
  const int mode = primitive.value("mode", 4);
  return mode == 4 || mode == 5 || mode == 6;
}

}  // namespace

Vec3d tile_origin(const Forest& f, const Tile& t) {
  return {f.extent_min[0] + (t.ix + 0.5) * f.tile_size_m, 0.0,
          f.extent_min[1] + (t.iz + 0.5) * f.tile_size_m};
}

std::string species_level_gltf(const LevelSource& level) {
  json g = level.gltf;
  if (!g.contains("buffers") || g["buffers"].size() != 1)
    throw std::invalid_argument("the level glTF must have exactly one buffer");
  if (!g.contains("meshes") || g["meshes"].size() != 1)
    throw std::invalid_argument("the level glTF must have exactly one mesh");
  g["buffers"][0]["uri"] = level.bin_name;
  if (g.contains("images"))
    for (auto& im : g["images"])
      if (im.contains("uri")) im["uri"] = level.image_prefix + im["uri"].get<std::string>();
  return g.dump(1) + "\n";
}

TileFiles tile_gltf(const Forest& forest, const Tile& tile, const std::vector<const LevelSource*>& levels,
                    const std::string& tile_bin_name, TileInstancing instancing) {
  const bool gpu = instancing == TileInstancing::kGpu;
  json out;
  out["asset"] = {{"version", "2.0"}, {"generator", "sylva"}};
  json buffers = json::array(), views = json::array(), accessors = json::array(), materials = json::array(),
       textures = json::array(), samplers = json::array(), images = json::array(), meshes = json::array(),
       nodes = json::array(), roots = json::array();
  std::vector<std::string> used, required;
  bool instanced = false;
  TileFiles files;
  const Vec3d origin = tile_origin(forest, tile);
  // Instances of the tile by species, in instance order.
  std::vector<std::vector<std::uint32_t>> by_species(forest.species.size());
  for (std::uint32_t i : tile.instances) by_species[forest.instances[i].species].push_back(i);
  const std::size_t tile_buffer_slot = 0;  // gpu: the tile's bin is buffer 0; species' bins follow
  if (gpu) buffers.push_back({{"uri", tile_bin_name}, {"byteLength", 0}});
  for (std::size_t s = 0; s < forest.species.size(); ++s) {
    if (by_species[s].empty()) continue;
    const LevelSource* src = levels.at(s);
    if (!src)
      throw std::invalid_argument("species '" + forest.species[s].name + "' has no level for this tile");
    const json& g = src->gltf;
    const std::size_t buf0 = buffers.size(), view0 = views.size(), acc0 = accessors.size(),
                      mat0 = materials.size(), tex0 = textures.size(), samp0 = samplers.size(),
                      img0 = images.size();
    buffers.push_back({{"uri", src->bin_name}, {"byteLength", src->bin_bytes}});
    for (json v : g.value("bufferViews", json::array())) {
      v["buffer"] = buf0;
      views.push_back(std::move(v));
    }
    for (json a : g.value("accessors", json::array())) {
      if (a.contains("bufferView")) a["bufferView"] = offset_index(a["bufferView"], view0);
      accessors.push_back(std::move(a));
    }
    for (json smp : g.value("samplers", json::array())) samplers.push_back(std::move(smp));
    for (json im : g.value("images", json::array())) {
      if (im.contains("uri")) im["uri"] = src->image_prefix + im["uri"].get<std::string>();
      if (im.contains("bufferView")) im["bufferView"] = offset_index(im["bufferView"], view0);
      images.push_back(std::move(im));
    }
    for (json t : g.value("textures", json::array())) {
      if (t.contains("sampler")) t["sampler"] = offset_index(t["sampler"], samp0);
      if (t.contains("source")) t["source"] = offset_index(t["source"], img0);
      textures.push_back(std::move(t));
    }
    for (json m : g.value("materials", json::array())) {
      std::function<void(json&)> fix = [&](json& j) {
        if (j.is_object()) {
          for (auto it = j.begin(); it != j.end(); ++it) {
            if (it.key() == "index" && it->is_number_unsigned())
              *it = offset_index(*it, tex0);
            else
              fix(*it);
          }
        } else if (j.is_array()) {
          for (auto& e : j) fix(e);
        }
      };
      fix(m);  // every textureInfo's "index" (baseColorTexture, normalTexture, ...)
      materials.push_back(std::move(m));
    }
    // The level's primitives split by kind: triangles go to the instanced mesh, lines and points
    // to a mesh each instance's own node draws (see tile_gltf.h).
    json mesh = g.at("meshes").at(0), loose = json::array();
    json& prims = mesh["primitives"];
    for (auto& p : prims) {
      for (auto& [name, acc] : p["attributes"].items()) acc = offset_index(acc, acc0);
      if (p.contains("indices")) p["indices"] = offset_index(p["indices"], acc0);
      if (p.contains("material")) p["material"] = offset_index(p["material"], mat0);
    }
    json triangles = json::array();
    for (auto& p : prims) (!gpu || triangle_mode(p) ? triangles : loose).push_back(std::move(p));
    std::optional<std::size_t> mesh_index, loose_index;
    if (!triangles.empty()) {
      prims = std::move(triangles);
      mesh_index = meshes.size();
      meshes.push_back(mesh);
    }
    if (!loose.empty()) {
      json m = {{"primitives", std::move(loose)}};
      if (mesh.contains("name")) m["name"] = mesh["name"].get<std::string>() + "_lines";
      loose_index = meshes.size();
      meshes.push_back(std::move(m));
    }
    for (const auto& e : g.value("extensionsUsed", json::array()))
      if (std::find(used.begin(), used.end(), e.get<std::string>()) == used.end())
        used.push_back(e.get<std::string>());
    for (const auto& e : g.value("extensionsRequired", json::array()))
      if (std::find(required.begin(), required.end(), e.get<std::string>()) == required.end())
        required.push_back(e.get<std::string>());

    // The instances (gpu): TRANSLATION, ROTATION, SCALE, _ID, each its own view in the tile's
    // bin. The per-tree nodes (the loose primitives' with gpu, the whole mesh's with nodes) carry
    // the same float values (printed as the shortest decimal of the float, gltf::float_json),
    // under a parent at the tile origin: both parts of a tree get one transform in every client.
    const auto& ids = by_species[s];
    std::string t, r, sc, id;
    json tree_nodes = json::array();
    double tmin[3] = {INFINITY, INFINITY, INFINITY}, tmax[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (std::uint32_t i : ids) {
      const Trs trs = instance_trs(forest.species[s], forest.instances[i]);
      json tj = json::array(), rj = json::array(), sj = json::array();
      for (int k = 0; k < 3; ++k) {
        const double v = trs.t[std::size_t(k)] - origin[std::size_t(k)];
        put_f32(t, v);
        const double fv = double(float(v));
        tmin[k] = std::min(tmin[k], fv);
        tmax[k] = std::max(tmax[k], fv);
        tj.push_back(gltf::float_json(fv));
      }
      for (double q : trs.r) {
        put_f32(r, q);
        rj.push_back(gltf::float_json(q));
      }
      for (double v : trs.s) {
        put_f32(sc, v);
        sj.push_back(gltf::float_json(v));
      }
      if (gpu && forest.instances[i].id >= (1u << 24))
        throw std::invalid_argument("instance ids from 2^24 on do not fit _ID (FLOAT)");
      put_f32(id, double(forest.instances[i].id));
      if (!gpu || loose_index)
        tree_nodes.push_back({{"mesh", gpu ? *loose_index : *mesh_index},
                              {"translation", tj},
                              {"rotation", rj},
                              {"scale", sj},
                              {"extras", {{"instance_id", forest.instances[i].id}}}});
    }
    auto add = [&](const std::string& data, const char* type, bool minmax) {
      const std::size_t offset = files.bin.size();
      files.bin += data;
      views.push_back({{"buffer", tile_buffer_slot}, {"byteOffset", offset}, {"byteLength", data.size()}});
      json a = {
          {"bufferView", views.size() - 1}, {"componentType", 5126}, {"count", ids.size()}, {"type", type}};
      if (minmax) {
        a["min"] = {tmin[0], tmin[1], tmin[2]};
        a["max"] = {tmax[0], tmax[1], tmax[2]};
      }
      accessors.push_back(std::move(a));
      return accessors.size() - 1;
    };
    if (gpu && mesh_index) {
      json attrs;
      attrs["TRANSLATION"] = add(t, "VEC3", true);
      attrs["ROTATION"] = add(r, "VEC4", false);
      attrs["SCALE"] = add(sc, "VEC3", false);
      attrs["_ID"] = add(id, "SCALAR", false);
      instanced = true;
      roots.push_back(nodes.size());
      nodes.push_back({{"name", forest.species[s].name},
                       {"mesh", *mesh_index},
                       {"translation", {origin[0], origin[1], origin[2]}},
                       {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attrs}}}}}});
    }
    if (!tree_nodes.empty()) {
      const std::size_t parent = nodes.size();
      json children = json::array();
      for (std::size_t k = 0; k < tree_nodes.size(); ++k) children.push_back(parent + 1 + k);
      roots.push_back(parent);
      nodes.push_back({{"name", forest.species[s].name + (gpu ? "_lines" : "")},
                       {"translation", {origin[0], origin[1], origin[2]}},
                       {"children", std::move(children)}});
      for (json& n : tree_nodes) nodes.push_back(std::move(n));
    }
  }
  if (gpu) buffers[tile_buffer_slot]["byteLength"] = files.bin.size();
  if (instanced) {
    used.insert(used.begin(), "EXT_mesh_gpu_instancing");
    required.insert(required.begin(), "EXT_mesh_gpu_instancing");
  }
  out["buffers"] = buffers;
  out["bufferViews"] = views;
  out["accessors"] = accessors;
  if (!materials.empty()) out["materials"] = materials;
  if (!textures.empty()) out["textures"] = textures;
  if (!samplers.empty()) out["samplers"] = samplers;
  if (!images.empty()) out["images"] = images;
  out["meshes"] = meshes;
  out["nodes"] = nodes;
  out["scenes"] = json::array({{{"nodes", roots}}});
  out["scene"] = 0;
  if (!used.empty()) out["extensionsUsed"] = used;
  if (!required.empty()) out["extensionsRequired"] = required;
  files.gltf = out.dump(1) + "\n";
  return files;
}

}  // namespace sylva::forest
