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

namespace {

// One species' instances in a tile as the tile stores them: the float streams of the instanced
// node's attributes (TRANSLATION relative to the tile origin, ROTATION, SCALE, _ID; little-endian
// f32), TRANSLATION's bounds, and the per-tree nodes.
struct TileInstances {
  std::string t, r, sc, id;
  double tmin[3] = {INFINITY, INFINITY, INFINITY}, tmax[3] = {-INFINITY, -INFINITY, -INFINITY};
  json tree_nodes = json::array();
};

// A tile's glTF while it is composed: every species' level resources appended with their indices
// offset, then its instances; `finish` writes the file.
class TileBuilder {
 public:
  TileBuilder(const Forest& forest, const Tile& tile, const std::string& tile_bin_name,
              TileInstancing instancing)
      : forest_(forest), gpu_(instancing == TileInstancing::kGpu), origin_(tile_origin(forest, tile)) {
    if (gpu_) buffers_.push_back({{"uri", tile_bin_name}, {"byteLength", 0}});
  }

  // Species s's level `src` and its instances `ids` (in instance order).
  void add_species(std::size_t s, const LevelSource& src, const std::vector<std::uint32_t>& ids) {
    const auto [mesh_index, loose_index] = append_level(src);
    const TileInstances in = encode_instances(s, ids, mesh_index, loose_index);
    if (gpu_ && mesh_index) add_instanced_node(s, in, ids.size(), *mesh_index);
    if (!in.tree_nodes.empty()) add_tree_nodes(s, in);
  }

  TileFiles finish() {
    if (gpu_) buffers_[kTileBufferSlot]["byteLength"] = files_.bin.size();
    if (instanced_) {
      used_.insert(used_.begin(), "EXT_mesh_gpu_instancing");
      required_.insert(required_.begin(), "EXT_mesh_gpu_instancing");
    }
    json out;
    out["asset"] = {{"version", "2.0"}, {"generator", "sylva"}};
    out["buffers"] = buffers_;
    out["bufferViews"] = views_;
    out["accessors"] = accessors_;
    if (!materials_.empty()) out["materials"] = materials_;
    if (!textures_.empty()) out["textures"] = textures_;
    if (!samplers_.empty()) out["samplers"] = samplers_;
    if (!images_.empty()) out["images"] = images_;
    out["meshes"] = meshes_;
    out["nodes"] = nodes_;
    out["scenes"] = json::array({{{"nodes", roots_}}});
    out["scene"] = 0;
    if (!used_.empty()) out["extensionsUsed"] = used_;
    if (!required_.empty()) out["extensionsRequired"] = required_;
    files_.gltf = out.dump(1) + "\n";
    return std::move(files_);
  }

 private:
  static constexpr std::size_t kTileBufferSlot = 0;  // gpu: the tile's bin is buffer 0; species' bins follow

  // The level's buffer, views, accessors, samplers, images, textures and materials appended
  // (indices offset), then its mesh split by kind: triangles go to the instanced mesh, lines and
  // points to a mesh each instance's own node draws (see tile_gltf.h); returns the indices of the
  // two meshes, when they have primitives.
  std::pair<std::optional<std::size_t>, std::optional<std::size_t>> append_level(const LevelSource& src) {
    const json& g = src.gltf;
    const std::size_t acc0 = accessors_.size(), mat0 = materials_.size();
    append_resources(src);
    json mesh = g.at("meshes").at(0), loose = json::array();
    json& prims = mesh["primitives"];
    for (auto& p : prims) {
      for (auto& [name, acc] : p["attributes"].items()) acc = offset_index(acc, acc0);
      if (p.contains("indices")) p["indices"] = offset_index(p["indices"], acc0);
      if (p.contains("material")) p["material"] = offset_index(p["material"], mat0);
    }
    json triangles = json::array();
    for (auto& p : prims) (!gpu_ || triangle_mode(p) ? triangles : loose).push_back(std::move(p));
    std::optional<std::size_t> mesh_index, loose_index;
    if (!triangles.empty()) {
      prims = std::move(triangles);
      mesh_index = meshes_.size();
      meshes_.push_back(mesh);
    }
    if (!loose.empty()) {
      json m = {{"primitives", std::move(loose)}};
      if (mesh.contains("name")) m["name"] = mesh["name"].get<std::string>() + "_lines";
      loose_index = meshes_.size();
      meshes_.push_back(std::move(m));
    }
    for (const auto& e : g.value("extensionsUsed", json::array()))
      if (std::find(used_.begin(), used_.end(), e.get<std::string>()) == used_.end())
        used_.push_back(e.get<std::string>());
    for (const auto& e : g.value("extensionsRequired", json::array()))
      if (std::find(required_.begin(), required_.end(), e.get<std::string>()) == required_.end())
        required_.push_back(e.get<std::string>());
    return {mesh_index, loose_index};
  }

  // Everything of the level but its mesh, each index offset past what the tile holds already.
  void append_resources(const LevelSource& src) {
    const json& g = src.gltf;
    const std::size_t buf0 = buffers_.size(), view0 = views_.size(), tex0 = textures_.size(),
                      samp0 = samplers_.size(), img0 = images_.size();
    buffers_.push_back({{"uri", src.bin_name}, {"byteLength", src.bin_bytes}});
    for (json v : g.value("bufferViews", json::array())) {
      v["buffer"] = buf0;
      views_.push_back(std::move(v));
    }
    for (json a : g.value("accessors", json::array())) {
      if (a.contains("bufferView")) a["bufferView"] = offset_index(a["bufferView"], view0);
      accessors_.push_back(std::move(a));
    }
    for (json smp : g.value("samplers", json::array())) samplers_.push_back(std::move(smp));
    for (json im : g.value("images", json::array())) {
      if (im.contains("uri")) im["uri"] = src.image_prefix + im["uri"].get<std::string>();
      if (im.contains("bufferView")) im["bufferView"] = offset_index(im["bufferView"], view0);
      images_.push_back(std::move(im));
    }
    for (json t : g.value("textures", json::array())) {
      if (t.contains("sampler")) t["sampler"] = offset_index(t["sampler"], samp0);
      if (t.contains("source")) t["source"] = offset_index(t["source"], img0);
      textures_.push_back(std::move(t));
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
      materials_.push_back(std::move(m));
    }
  }

  // The instances (gpu): TRANSLATION, ROTATION, SCALE, _ID streams. The per-tree nodes (the loose
  // primitives' with gpu, the whole mesh's with nodes) carry the same float values (printed as
  // the shortest decimal of the float, gltf::float_json), under a parent at the tile origin: both
  // parts of a tree get one transform in every client.
  TileInstances encode_instances(std::size_t s, const std::vector<std::uint32_t>& ids,
                                 std::optional<std::size_t> mesh_index,
                                 std::optional<std::size_t> loose_index) {
    TileInstances out;
    for (std::uint32_t i : ids) {
      const Trs trs = instance_trs(forest_.species[s], forest_.instances[i]);
      json tj = json::array(), rj = json::array(), sj = json::array();
      for (int k = 0; k < 3; ++k) {
        const double v = trs.t[std::size_t(k)] - origin_[std::size_t(k)];
        put_f32(out.t, v);
        const double fv = double(float(v));
        out.tmin[k] = std::min(out.tmin[k], fv);
        out.tmax[k] = std::max(out.tmax[k], fv);
        tj.push_back(gltf::float_json(fv));
      }
      for (double q : trs.r) {
        put_f32(out.r, q);
        rj.push_back(gltf::float_json(q));
      }
      for (double v : trs.s) {
        put_f32(out.sc, v);
        sj.push_back(gltf::float_json(v));
      }
      if (gpu_ && forest_.instances[i].id >= (1u << 24))
        throw std::invalid_argument("instance ids from 2^24 on do not fit _ID (FLOAT)");
      put_f32(out.id, double(forest_.instances[i].id));
      if (!gpu_ || loose_index)
        out.tree_nodes.push_back({{"mesh", gpu_ ? *loose_index : *mesh_index},
                                  {"translation", tj},
                                  {"rotation", rj},
                                  {"scale", sj},
                                  {"extras", {{"instance_id", forest_.instances[i].id}}}});
    }
    return out;
  }

  // One stream of `count` floats of `type` as a view of the tile's bin and its accessor (with
  // TRANSLATION's bounds when `in` is given); returns the accessor's index.
  std::size_t add_stream(const std::string& data, const char* type, std::size_t count,
                         const TileInstances* in) {
    const std::size_t offset = files_.bin.size();
    files_.bin += data;
    views_.push_back({{"buffer", kTileBufferSlot}, {"byteOffset", offset}, {"byteLength", data.size()}});
    json a = {{"bufferView", views_.size() - 1}, {"componentType", 5126}, {"count", count}, {"type", type}};
    if (in) {
      a["min"] = {in->tmin[0], in->tmin[1], in->tmin[2]};
      a["max"] = {in->tmax[0], in->tmax[1], in->tmax[2]};
    }
    accessors_.push_back(std::move(a));
    return accessors_.size() - 1;
  }

  // The species' node at the tile origin drawing its triangle mesh once per instance.
  void add_instanced_node(std::size_t s, const TileInstances& in, std::size_t count, std::size_t mesh_index) {
    json attrs;
    attrs["TRANSLATION"] = add_stream(in.t, "VEC3", count, &in);
    attrs["ROTATION"] = add_stream(in.r, "VEC4", count, nullptr);
    attrs["SCALE"] = add_stream(in.sc, "VEC3", count, nullptr);
    attrs["_ID"] = add_stream(in.id, "SCALAR", count, nullptr);
    instanced_ = true;
    roots_.push_back(nodes_.size());
    nodes_.push_back({{"name", forest_.species[s].name},
                      {"mesh", mesh_index},
                      {"translation", {origin_[0], origin_[1], origin_[2]}},
                      {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attrs}}}}}});
  }

  // The per-tree nodes under one parent at the tile origin.
  void add_tree_nodes(std::size_t s, const TileInstances& in) {
    const std::size_t parent = nodes_.size();
    json children = json::array();
    for (std::size_t k = 0; k < in.tree_nodes.size(); ++k) children.push_back(parent + 1 + k);
    roots_.push_back(parent);
    nodes_.push_back({{"name", forest_.species[s].name + (gpu_ ? "_lines" : "")},
                      {"translation", {origin_[0], origin_[1], origin_[2]}},
                      {"children", std::move(children)}});
    for (const json& n : in.tree_nodes) nodes_.push_back(n);
  }

  const Forest& forest_;
  const bool gpu_;
  const Vec3d origin_;
  json buffers_ = json::array(), views_ = json::array(), accessors_ = json::array(),
       materials_ = json::array(), textures_ = json::array(), samplers_ = json::array(),
       images_ = json::array(), meshes_ = json::array(), nodes_ = json::array(), roots_ = json::array();
  std::vector<std::string> used_, required_;
  bool instanced_ = false;
  TileFiles files_;
};

}  // namespace

TileFiles tile_gltf(const Forest& forest, const Tile& tile, const std::vector<const LevelSource*>& levels,
                    const std::string& tile_bin_name, TileInstancing instancing) {
  // Instances of the tile by species, in instance order.
  std::vector<std::vector<std::uint32_t>> by_species(forest.species.size());
  for (std::uint32_t i : tile.instances) by_species[forest.instances[i].species].push_back(i);
  TileBuilder b(forest, tile, tile_bin_name, instancing);
  for (std::size_t s = 0; s < forest.species.size(); ++s) {
    if (by_species[s].empty()) continue;
    const LevelSource* src = levels.at(s);
    if (!src)
      throw std::invalid_argument("species '" + forest.species[s].name + "' has no level for this tile");
    b.add_species(s, *src, by_species[s]);
  }
  return b.finish();
}

}  // namespace sylva::forest
