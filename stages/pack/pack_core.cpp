// Issue 14 "The chain per species" and "Compression and size", for the mesh levels the lod
// stage proved (each level's epsilon, delta and switch distance come from its lod.gltf node).
#include "stages/pack/pack_core.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "libs/gltf/optimize.h"
#include "libs/gltf/writer.h"
#include "libs/pack/lod_json.h"

namespace sylva::pack {

namespace {

double number(const nlohmann::json& extras, const char* key, const std::string& where) {
  if (!extras.is_object() || !extras.contains(key) || !extras[key].is_number())
    throw std::invalid_argument(where + " has no numeric extras." + key);
  return extras[key].get<double>();
}

void count_primitives(const gltf::Scene& s, LodLevel& l) {
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) {
      const std::size_t n = p.indices.empty() ? p.vertex_count() : p.indices.size();
      if (p.mode == gltf::PrimitiveMode::kTriangles) l.triangles += n / 3;
      if (p.mode == gltf::PrimitiveMode::kLines) l.lines += n / 2;
    }
}

}  // namespace

PositionGrid position_grid(const gltf::Mesh& mesh, double epsilon, double fraction) {
  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const auto& p : mesh.primitives)
    for (std::size_t i = 0; i < p.positions.size(); ++i) {
      lo[i % 3] = std::min<double>(lo[i % 3], p.positions[i]);
      hi[i % 3] = std::max<double>(hi[i % 3], p.positions[i]);
    }
  double extent = 0;
  for (std::size_t c = 0; c < 3; ++c) extent = std::max(extent, hi[c] - lo[c]);
  const double budget = fraction * epsilon;  // allowed rounding error, m
  if (!(budget > 0) || !(extent >= 0)) return {};
  const double half_diagonal = std::sqrt(3.0) / 2;
  for (int bits = 1; bits <= 16; ++bits) {
    const double step = extent / double((1u << bits) - 1);
    if (half_diagonal * step <= budget) return {bits, half_diagonal * step};
  }
  return {};
}

std::vector<PackedFile> pack_species(const SpeciesInput& in, const PackOptions& options) {
  const gltf::Scene& chain = in.chain;
  if (chain.roots.size() != 1 || chain.roots[0] < 0 || std::size_t(chain.roots[0]) >= chain.nodes.size())
    throw std::invalid_argument("the lod chain has not exactly one root node");
  const gltf::Node& root = chain.nodes[std::size_t(chain.roots[0])];
  const nlohmann::json& ids = root.extensions.is_object()
                                  ? root.extensions.value("MSFT_lod", nlohmann::json())["ids"]
                                  : nlohmann::json();
  if (!ids.is_array() || ids.size() + 1 != in.levels.size())
    throw std::invalid_argument("the lod chain's MSFT_lod names " +
                                std::to_string(ids.is_array() ? ids.size() + 1 : 0) + " levels, but " +
                                std::to_string(in.levels.size()) + " level files were given");
  const nlohmann::json& coverage =
      root.extras.is_object() ? root.extras.value("MSFT_screencoverage", nlohmann::json()) : nlohmann::json();
  if (!coverage.is_array() || coverage.size() != in.levels.size())
    throw std::invalid_argument("the lod chain's root has no MSFT_screencoverage for every level");

  gltf::WriteOptions w;
  w.format = gltf::FileFormat::kGlb;
  w.meshopt = options.compression == Compression::kMeshopt;
  w.draco.enabled = options.compression == Compression::kDraco;
  w.quantize.enabled = options.quantize && !w.draco.enabled;
  w.quantize.normal_bits = options.normal_bits;
  w.quantize.texcoord_bits = options.texcoord_bits;
  // `position_bits` (grids) and `float_error` (the bound for float positions, meshopt's EXPONENTIAL
  // filter) have one entry per mesh of the scene being encoded.
  auto encode = [&](gltf::Scene s, std::vector<int> position_bits, std::vector<double> float_error) {
    w.quantize.position_bits = std::move(position_bits);
    w.quantize.float_position_error = std::move(float_error);
    if (options.optimize) gltf::optimize_scene(s);
    nlohmann::json extras = s.extras.is_object() ? s.extras : nlohmann::json::object();
    extras["sylva_stage"] = "pack";
    extras["species"] = in.species;
    s.extras = std::move(extras);
    return gltf::encode(s, w);
  };

  // Each level's numbers and position grid, from its node in the chain.
  LodDescription d;
  d.species = in.species;
  d.chain = in.species + ".glb";
  std::vector<int> chain_bits(chain.meshes.size(), 0);
  std::vector<double> chain_float_error(chain.meshes.size(), 0.0);
  std::vector<double> level_float_error;  // per level: the bound for float positions (EXPONENTIAL)
  std::vector<std::vector<int>> level_bits;
  for (std::size_t i = 0; i < in.levels.size(); ++i) {
    const int node = i == 0 ? chain.roots[0] : ids[i - 1].get<int>();
    if (node < 0 || std::size_t(node) >= chain.nodes.size())
      throw std::invalid_argument("MSFT_lod names node " + std::to_string(node) + ", which does not exist");
    const gltf::Node& n = chain.nodes[std::size_t(node)];
    const std::string where = "level " + std::to_string(i) + " (node " + std::to_string(node) + ")";
    LodLevel l;
    l.file = in.species + "_lod" + std::to_string(i) + ".glb";
    l.epsilon_m = number(n.extras, "epsilon_m", where);
    l.pixel_error_px = number(n.extras, "pixel_error_px", where);
    l.switch_distance_m = number(n.extras, "switch_distance_m", where);
    l.screen_coverage = coverage[i].get<double>();
    count_primitives(in.levels[i], l);
    std::vector<int> bits(in.levels[i].meshes.size(), 0);
    if (w.quantize.enabled) {
      // The level file's meshes and the chain node's mesh hold the same level: the same grid.
      for (std::size_t m = 0; m < bits.size(); ++m) {
        const PositionGrid g = position_grid(in.levels[i].meshes[m], l.epsilon_m, options.position_error);
        bits[m] = g.bits;
        l.position_bits = std::max(l.position_bits, g.bits);
        l.position_error_m = std::max(l.position_error_m, g.max_error_m);
        if (g.bits == 0) {
          l.position_float = true;
          // Float positions: exact, or within position_error x epsilon through the EXPONENTIAL filter.
          if (w.meshopt)
            l.position_error_m = std::max(l.position_error_m, options.position_error * l.epsilon_m);
        }
      }
      if (n.mesh >= 0 && std::size_t(n.mesh) < chain.meshes.size()) {
        const PositionGrid g =
            position_grid(chain.meshes[std::size_t(n.mesh)], l.epsilon_m, options.position_error);
        chain_bits[std::size_t(n.mesh)] = g.bits;
        chain_float_error[std::size_t(n.mesh)] = options.position_error * l.epsilon_m;
      }
    } else {
      l.position_float = true;
    }
    level_bits.push_back(std::move(bits));
    level_float_error.push_back(w.quantize.enabled ? options.position_error * l.epsilon_m : 0.0);
    d.levels.push_back(l);
  }

  std::vector<PackedFile> out;
  out.push_back({d.chain, encode(chain, chain_bits, chain_float_error), in.chain_inputs});
  for (std::size_t i = 0; i < in.levels.size(); ++i) {
    std::string bytes = encode(in.levels[i], level_bits[i],
                               std::vector<double>(in.levels[i].meshes.size(), level_float_error[i]));
    d.levels[i].bytes = bytes.size();
    out.push_back({d.levels[i].file, std::move(bytes),
                   i < in.level_inputs.size() ? in.level_inputs[i] : std::vector<std::string>{}});
  }
  out.push_back({in.species + ".lod.json", write_lod_json(d), in.chain_inputs});
  return out;
}

}  // namespace sylva::pack
