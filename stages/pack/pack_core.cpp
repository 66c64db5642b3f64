// Issue 14 "The chain per species" and "Compression and size", for the mesh levels the lod
// stage proved (each level's epsilon, delta and switch distance come from its lod.gltf node).
#include "stages/pack/pack_core.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <list>
#include <numbers>
#include <stdexcept>

#include "libs/gltf/compose.h"
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

// The keys of a mesh level's node extras the pack keeps (a level's numbers; lod.json has them
// and more). The lod stage's diagnostics (E1_m..E5_m, line alphas, polygon error, counts) and its
// mesh extras (the same again) stay in the lod artifact (a smaller JSON chunk in every file).
nlohmann::json level_node_extras(const nlohmann::json& extras) {
  nlohmann::json out = nlohmann::json::object();
  if (!extras.is_object()) return out;
  for (const char* key : {"sylva_lod_level", "epsilon_m", "pixel_error_px", "switch_distance_m"})
    if (extras.contains(key)) out[key] = extras[key];
  return out;
}

gltf::Scene lean_level(const gltf::Scene& level) {
  gltf::Scene s = level;
  for (gltf::Mesh& m : s.meshes) m.extras = nullptr;
  for (gltf::Node& n : s.nodes) n.extras = level_node_extras(n.extras);
  return s;
}

}  // namespace

PositionGrid position_grid(const gltf::Mesh& mesh, double epsilon, double fraction, double max_fraction) {
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
    if (half_diagonal * step <= budget) return {bits, half_diagonal * step, false};
  }
  // KHR_mesh_quantization stops at 16 bits. Its grid is still far finer than the level's own
  // error when it rounds within max_fraction x epsilon, and far smaller than float positions.
  const double step16 = extent / double((1u << 16) - 1);
  if (half_diagonal * step16 <= max_fraction * epsilon) return {16, half_diagonal * step16, true};
  return {};
}

namespace {

// The numbers of mesh level i, from its node in the lod chain (level 0: the root).
struct ChainLevel {
  const gltf::Node* node = nullptr;
  double epsilon_m = 0, pixel_error_px = 0, switch_distance_m = 0, coverage = 0;
};

struct ParsedChain {
  std::vector<ChainLevel> levels;
  std::vector<double> coverage;  // the chain's MSFT_screencoverage
};

ParsedChain parse_chain(const SpeciesInput& in) {
  const gltf::Scene& chain = in.chain;
  if (chain.roots.size() != 1 || chain.roots[0] < 0 || std::size_t(chain.roots[0]) >= chain.nodes.size())
    throw std::invalid_argument("the lod chain has not exactly one root node");
  const gltf::Node& root = chain.nodes[std::size_t(chain.roots[0])];
  const nlohmann::json no_ids = nlohmann::json::array();
  const nlohmann::json& ids = root.extensions.is_object() && root.extensions.contains("MSFT_lod")
                                  ? root.extensions["MSFT_lod"].value("ids", no_ids)
                                  : no_ids;
  if (!ids.is_array() || ids.size() + 1 != in.levels.size())
    throw std::invalid_argument("the lod chain's MSFT_lod names " +
                                std::to_string(ids.is_array() ? ids.size() + 1 : 0) + " levels, but " +
                                std::to_string(in.levels.size()) + " level files were given");
  const nlohmann::json& coverage =
      root.extras.is_object() ? root.extras.value("MSFT_screencoverage", nlohmann::json()) : nlohmann::json();
  if (!coverage.is_array() || coverage.size() != in.levels.size())
    throw std::invalid_argument("the lod chain's root has no MSFT_screencoverage for every level");
  ParsedChain out;
  for (std::size_t i = 0; i < in.levels.size(); ++i) {
    const int node = i == 0 ? chain.roots[0] : (ids[i - 1].is_number_integer() ? ids[i - 1].get<int>() : -1);
    if (node < 0 || std::size_t(node) >= chain.nodes.size())
      throw std::invalid_argument("MSFT_lod names node " + std::to_string(node) + ", which does not exist");
    const gltf::Node& n = chain.nodes[std::size_t(node)];
    const std::string where = "level " + std::to_string(i) + " (node " + std::to_string(node) + ")";
    if (!coverage[i].is_number())
      throw std::invalid_argument("MSFT_screencoverage[" + std::to_string(i) + "] is not a number");
    ChainLevel l;
    l.node = &n;
    l.epsilon_m = number(n.extras, "epsilon_m", where);
    l.pixel_error_px = number(n.extras, "pixel_error_px", where);
    l.switch_distance_m = number(n.extras, "switch_distance_m", where);
    l.coverage = coverage[i].get<double>();
    out.coverage.push_back(l.coverage);
    out.levels.push_back(l);
  }
  return out;
}

std::uint64_t primitives_of(const gltf::Scene& s) {
  LodLevel l;
  count_primitives(s, l);
  std::uint64_t points = 0;
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives)
      if (p.mode == gltf::PrimitiveMode::kPoints)
        points += p.indices.empty() ? p.vertex_count() : p.indices.size();
  return l.triangles + l.lines + points;
}

// Half the diagonal of the axis-aligned box of every position of the scene's meshes: the
// bounding sphere the lod stage's MSFT_screencoverage is for (lod_gltf.h bounding_radius).
double bounding_radius(const gltf::Scene& s) {
  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives)
      for (std::size_t i = 0; i < p.positions.size(); ++i) {
        lo[i % 3] = std::min<double>(lo[i % 3], p.positions[i]);
        hi[i % 3] = std::max<double>(hi[i % 3], p.positions[i]);
      }
  if (!(lo[0] <= hi[0])) return 0;
  double d2 = 0;
  for (int c = 0; c < 3; ++c) d2 += (hi[c] - lo[c]) * (hi[c] - lo[c]);
  return 0.5 * std::sqrt(d2);
}

// MSFT_screencoverage at distance d (lod_gltf.h screen_coverages): pi R^2 / (2 d tan(phi/2))^2,
// clamped to 1.
double coverage_at(double radius, double tan_half_fov, double d) {
  const double c = std::numbers::pi * radius * radius / ((2 * d * tan_half_fov) * (2 * d * tan_half_fov));
  return std::min(1.0, c);
}

}  // namespace

std::vector<LevelChoice> select_levels(const SpeciesInput& in, const PackOptions& options) {
  const ParsedChain chain = parse_chain(in);
  if (!(options.min_saving >= 0 && options.min_saving < 1))
    throw std::invalid_argument("min_saving must lie in [0, 1)");
  std::vector<LevelChoice> out;
  const double keep_at_most = 1 - options.min_saving;
  const LevelChoice* previous = nullptr;  // the level kept last
  auto too_little = [&](const LevelChoice& c) {
    return previous && double(c.primitives) > keep_at_most * double(previous->primitives);
  };
  auto saving_reason = [&](const LevelChoice& c) {
    const double saved =
        previous->primitives == 0 ? 0 : 1 - double(c.primitives) / double(previous->primitives);
    char buf[160];
    std::snprintf(
        buf, sizeof buf,
        "saves %.3g of the primitives of the level before it (%llu -> %llu), less than min_saving %.3g",
        saved, static_cast<unsigned long long>(previous->primitives),
        static_cast<unsigned long long>(c.primitives), options.min_saving);
    return std::string(buf);
  };
  out.reserve(in.levels.size() + 1);
  for (std::size_t i = 0; i < in.levels.size(); ++i) {
    LevelChoice c;
    c.source_level = i;
    c.switch_distance_m = chain.levels[i].switch_distance_m;
    c.primitives = primitives_of(in.levels[i]);
    if (i == 0) {
      c.kept = true;
    } else if (in.impostor && c.switch_distance_m >= in.impostor->switch_distance_m) {
      char buf[160];
      std::snprintf(buf, sizeof buf,
                    "the impostor is proven from %.6g m, before this level's switch distance %.6g m",
                    in.impostor->switch_distance_m, c.switch_distance_m);
      c.reason = buf;
    } else if (too_little(c)) {
      c.reason = saving_reason(c);
    } else {
      c.kept = true;
    }
    out.push_back(c);
    if (out.back().kept) previous = &out.back();
  }
  if (in.impostor) {
    LevelChoice c;
    c.impostor = true;
    c.switch_distance_m = std::max(in.impostor->switch_distance_m, chain.levels[0].switch_distance_m);
    c.primitives = primitives_of(in.impostor->scene);
    if (too_little(c))
      c.reason = saving_reason(c);
    else
      c.kept = true;
    out.push_back(c);
  }
  return out;
}

std::vector<PackedFile> pack_species(const SpeciesInput& in, const PackOptions& options,
                                     LodDescription* description) {
  const ParsedChain parsed = parse_chain(in);
  const std::vector<LevelChoice> choice = select_levels(in, options);

  // The camera's tan(phi/2): from the impostor's camera, checked against the chain's coverages
  // (c_i is the coverage at level i + 1's switch distance; any unclamped one fixes tan(phi/2)).
  const double radius = bounding_radius(in.levels[0]);
  double tan_half = 0;
  for (std::size_t i = 0; i + 1 < parsed.levels.size() && tan_half == 0; ++i) {
    const double c = parsed.coverage[i];
    if (c > 0 && c < 1 && radius > 0)
      tan_half = radius * std::sqrt(std::numbers::pi / c) / (2 * parsed.levels[i + 1].switch_distance_m);
  }
  if (in.impostor) {
    const double t = std::tan(in.impostor->fov_y_rad / 2);
    if (tan_half > 0 && std::abs(t - tan_half) > 1e-4 * tan_half)
      throw std::invalid_argument("the impostor's camera (vertical fov " +
                                  std::to_string(in.impostor->fov_y_rad * 180 / std::numbers::pi) +
                                  " deg) is not the lod chain's (" +
                                  std::to_string(2 * std::atan(tan_half) * 180 / std::numbers::pi) +
                                  " deg): its switch distance is for another view");
    tan_half = t;
  }

  gltf::WriteOptions w;
  w.format = gltf::FileFormat::kGlb;
  w.meshopt = options.compression == Compression::kMeshopt;
  w.meshopt_merge_views = w.meshopt;
  w.draco.enabled = options.compression == Compression::kDraco;
  w.quantize.enabled = options.quantize && !w.draco.enabled;
  w.quantize.normal_bits = options.normal_bits;
  w.quantize.texcoord_bits = options.texcoord_bits;
  // `position_bits` (grids) and `float_error` (the bound for float positions, meshopt's EXPONENTIAL
  // filter) have one entry per mesh of the scene being encoded.
  auto encode = [&](gltf::Scene s, std::vector<int> position_bits, std::vector<double> float_error) {
    w.quantize.position_bits = std::move(position_bits);
    w.quantize.float_position_error = std::move(float_error);
    if (options.optimize) gltf::optimize_scene(s, gltf::OptimizeOrder::kSize);
    nlohmann::json extras = s.extras.is_object() ? s.extras : nlohmann::json::object();
    extras["sylva_stage"] = "pack";
    extras["species"] = in.species;
    s.extras = std::move(extras);
    return gltf::encode(s, w);
  };

  // The kept levels, nearest first: their scenes, numbers and position grids.
  struct Kept {
    const gltf::Scene* scene;
    nlohmann::json node_extras;
    std::vector<std::string> inputs;
    LodLevel level;
    std::vector<int> bits;  // per mesh of `scene`
    double float_error = 0;
  };
  std::vector<Kept> kept;
  std::list<gltf::Scene> lean;  // the kept mesh levels without the lod stage's diagnostics (stable addresses)
  LodDescription d;
  d.species = in.species;
  d.chain = in.species + ".glb";
  std::size_t mesh_index = 0;
  for (const LevelChoice& c : choice) {
    if (!c.kept) {
      d.dropped.push_back({c.impostor ? "impostor" : "mesh", c.impostor ? -1 : int(c.source_level),
                           c.switch_distance_m, c.primitives, c.reason});
      continue;
    }
    Kept k;
    LodLevel& l = k.level;
    if (c.impostor) {
      const ImpostorLevelInput& im = *in.impostor;
      k.scene = &im.scene;
      k.inputs = im.inputs;
      l.file = in.species + "_impostor.glb";
      l.kind = "impostor";
      l.impostor_kind = im.kind;
      l.source_level = -1;
      l.epsilon_m = im.epsilon_m;
      l.pixel_error_px = im.pixel_error_px;
      k.node_extras = {{"sylva_lod_level", kept.size()},
                       {"kind", "impostor"},
                       {"impostor_kind", im.kind},
                       {"epsilon_m", im.epsilon_m},
                       {"pixel_error_px", im.pixel_error_px},
                       {"switch_distance_m", c.switch_distance_m}};
    } else {
      const ChainLevel& cl = parsed.levels[c.source_level];
      k.scene = &lean.emplace_back(lean_level(in.levels[c.source_level]));
      k.inputs = c.source_level < in.level_inputs.size() ? in.level_inputs[c.source_level]
                                                         : std::vector<std::string>{};
      l.file = in.species + "_lod" + std::to_string(mesh_index++) + ".glb";
      l.source_level = int(c.source_level);
      l.epsilon_m = cl.epsilon_m;
      l.pixel_error_px = cl.pixel_error_px;
      k.node_extras = level_node_extras(cl.node->extras);
    }
    l.switch_distance_m = c.switch_distance_m;
    count_primitives(*k.scene, l);
    l.primitives = c.primitives;
    k.bits.assign(k.scene->meshes.size(), 0);
    if (w.quantize.enabled) {
      for (std::size_t m = 0; m < k.bits.size(); ++m) {
        const PositionGrid g = position_grid(k.scene->meshes[m], l.epsilon_m, options.position_error,
                                             options.position_error_max);
        k.bits[m] = g.bits;
        l.position_bits = std::max(l.position_bits, g.bits);
        l.position_error_m = std::max(l.position_error_m, g.max_error_m);
        if (g.bits == 0) {
          l.position_float = true;
          // Float positions: exact, or within position_error x epsilon through the EXPONENTIAL filter.
          if (w.meshopt)
            l.position_error_m = std::max(l.position_error_m, options.position_error * l.epsilon_m);
        }
      }
      k.float_error = options.position_error * l.epsilon_m;
    } else {
      l.position_float = true;
    }
    kept.push_back(std::move(k));
  }

  // Screen coverage of kept level k: the coverage at the next kept level's switch distance. A
  // mesh level j after it: the lod chain's value c_{j-1} (the coverage at level j's switch
  // distance, as the lod stage computed it); the impostor: computed with the impostor's camera.
  for (std::size_t k = 0; k < kept.size(); ++k) {
    double c = 0;
    if (k + 1 < kept.size()) {
      const Kept& next = kept[k + 1];
      c = next.level.kind == "impostor" ? coverage_at(radius, tan_half, next.level.switch_distance_m)
                                        : parsed.coverage[std::size_t(next.level.source_level) - 1];
    }
    kept[k].level.screen_coverage = c;
  }

  // The chain: every kept level's scene appended (images and materials shared), one node per
  // level; the first is the scene's root with MSFT_lod naming the others.
  gltf::Scene chain;
  chain.generator = in.chain.generator;
  chain.extras = in.chain.extras;
  std::vector<int> chain_bits;
  std::vector<double> chain_float_error;
  std::vector<int> level_nodes;
  nlohmann::json coverage = nlohmann::json::array();
  for (Kept& k : kept) {
    const std::size_t first_mesh = chain.meshes.size();
    const std::vector<int> roots = gltf::append_scene(chain, *k.scene);
    if (roots.size() != 1)
      throw std::invalid_argument(k.level.file + ": the level's scene has " + std::to_string(roots.size()) +
                                  " root nodes, expected 1");
    gltf::Node& n = chain.nodes[std::size_t(roots[0])];
    n.extras = k.node_extras;
    n.extensions = nullptr;
    level_nodes.push_back(roots[0]);
    for (std::size_t m = first_mesh; m < chain.meshes.size(); ++m) {
      chain_bits.push_back(k.bits[m - first_mesh]);
      chain_float_error.push_back(k.float_error);
    }
    coverage.push_back(k.level.screen_coverage);
  }
  chain.roots = {level_nodes[0]};
  gltf::Node& root = chain.nodes[std::size_t(level_nodes[0])];
  root.extras["MSFT_screencoverage"] = coverage;
  if (level_nodes.size() >= 2) {
    nlohmann::json ids = nlohmann::json::array();
    for (std::size_t i = 1; i < level_nodes.size(); ++i) ids.push_back(level_nodes[i]);
    root.extensions = {{"MSFT_lod", {{"ids", ids}}}};
  }
  std::vector<std::string> chain_inputs = in.chain_inputs;
  if (in.impostor)
    chain_inputs.insert(chain_inputs.end(), in.impostor->inputs.begin(), in.impostor->inputs.end());

  std::vector<PackedFile> out;
  out.push_back({d.chain, encode(std::move(chain), chain_bits, chain_float_error), chain_inputs});
  for (Kept& k : kept) {
    std::string bytes = encode(*k.scene, k.bits, std::vector<double>(k.scene->meshes.size(), k.float_error));
    k.level.bytes = bytes.size();
    out.push_back({k.level.file, std::move(bytes), k.inputs});
    d.levels.push_back(k.level);
  }
  out.push_back({in.species + ".lod.json", write_lod_json(d), chain_inputs});
  if (description) *description = std::move(d);
  return out;
}

}  // namespace sylva::pack
