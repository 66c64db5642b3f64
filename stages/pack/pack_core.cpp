// Issue 14 "The chain per species" and "Compression and size", for the mesh levels the lod
// stage proved (each level's epsilon, delta and switch distance come from its lod.gltf node).
#include "stages/pack/pack_core.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "libs/gltf/compose.h"
#include "libs/gltf/optimize.h"
#include "libs/gltf/writer.h"
#include "libs/image/png.h"
#include "libs/lodchain/chain_gltf.h"
#include "libs/lodmodel/lod_model.h"
#include "libs/pack/lod_json.h"

namespace sylva::pack {

namespace {

void count_primitives(const gltf::Scene& s, LodLevel& l) {
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) {
      const std::size_t n = p.indices.empty() ? p.vertex_count() : p.indices.size();
      if (p.mode == gltf::PrimitiveMode::kTriangles) l.triangles += n / 3;
      if (p.mode == gltf::PrimitiveMode::kLines) l.lines += n / 2;
    }
}

// A mesh level's nodes and meshes from index `first_node` / `first_mesh` on, in the copy of the
// scene that is being encoded: only the level's numbers in the nodes' extras
// (lodchain::level_number_extras; lod.json has them and more), none in the meshes'. The lod
// stage's diagnostics (E1_m..E5_m, line alphas, polygon error, counts) and its mesh extras (the
// same again) stay in the lod artifact (a smaller JSON chunk in every file).
void trim_level_extras(gltf::Scene& s, std::size_t first_node, std::size_t first_mesh) {
  for (std::size_t m = first_mesh; m < s.meshes.size(); ++m) s.meshes[m].extras = nullptr;
  for (std::size_t n = first_node; n < s.nodes.size(); ++n)
    s.nodes[n].extras = lodchain::level_number_extras(s.nodes[n].extras);
}

}  // namespace

namespace {

// The largest axis extent of the mesh's positions (m): what its position grid spans.
double mesh_extent(const gltf::Mesh& mesh) {
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
  return extent;
}

// sqrt(3)/2 of a step of a `bits` grid over `extent`: the largest rounding error (m).
double grid_error(double extent, int bits) {
  return std::sqrt(3.0) / 2 * (extent / double((1u << bits) - 1));
}

}  // namespace

PositionGrid position_grid(const gltf::Mesh& mesh, double epsilon, double fraction, double max_fraction) {
  const double extent = mesh_extent(mesh);
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

// The chain's MSFT_lod links and every level's numbers (lodchain::read_chain_levels).
ParsedChain parse_chain(const SpeciesInput& in) {
  const gltf::Scene& chain = in.chain;
  const std::vector<lodchain::ChainLevelNumbers> levels =
      lodchain::read_chain_levels(chain.roots, chain.nodes.size(), in.levels.size(), [&](std::size_t n) {
        return lodchain::ChainNode{&chain.nodes[n].extras, &chain.nodes[n].extensions};
      });
  ParsedChain out;
  for (const lodchain::ChainLevelNumbers& n : levels) {
    ChainLevel l;
    l.node = &chain.nodes[std::size_t(n.node)];
    l.epsilon_m = n.epsilon_m;
    l.pixel_error_px = n.pixel_error_px;
    l.switch_distance_m = n.switch_distance_m;
    l.coverage = n.screen_coverage;
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

// The radius of the bounding sphere the lod stage's MSFT_screencoverage is for: the
// lodmodel::BoundingBox of every position of the scene's meshes (level 0's, as the lod stage).
double bounding_radius(const gltf::Scene& s) {
  lodmodel::BoundingBox box;
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) box.extend(p.positions);
  return box.radius();
}

}  // namespace

namespace {

// A candidate level (mesh levels in lod order, then the impostor) ready to encode: its scene, the
// numbers the lod stage or impostor.json gave it, and its position grid (per mesh).
struct Candidate {
  bool impostor = false;
  std::size_t source_level = 0;
  const gltf::Scene* scene = nullptr;
  double epsilon_m = 0, pixel_error_px = 0;
  double switch_distance_m = 0;  // its own (proven) switch distance
  std::uint64_t primitives = 0;
  std::vector<int> bits;  // per mesh of `scene`
  // Per mesh: its extent, and whether its grid has more than position_bits_min bits or float
  // positions (with a meter, a coarser grid that measures as passing).
  std::vector<double> extent;
  std::vector<char> fine;
  double float_error = 0;
  LodLevel grid;  // position_bits, position_error_m, position_float
};

// The chain parsed and every candidate prepared, and the writer's options: what both the level
// choice (which measures the files as shipped) and pack_species need.
class Prepared {
 public:
  Prepared(const SpeciesInput& in, const PackOptions& options) : in_(in), options_(options) {
    parsed = parse_chain(in);
    if (!(options.min_saving >= 0 && options.min_saving < 1))
      throw std::invalid_argument("min_saving must lie in [0, 1)");
    w.format = gltf::FileFormat::kGlb;
    w.meshopt = options.compression == Compression::kMeshopt;
    w.meshopt_merge_views = w.meshopt;
    w.draco.enabled = options.compression == Compression::kDraco;
    w.quantize.enabled = options.quantize && !w.draco.enabled;
    w.quantize.normal_bits = options.normal_bits;
    w.quantize.texcoord_bits = options.texcoord_bits;
    for (std::size_t i = 0; i < in.levels.size(); ++i) {
      Candidate c;
      c.source_level = i;
      c.scene = &in.levels[i];
      c.epsilon_m = parsed.levels[i].epsilon_m;
      c.pixel_error_px = parsed.levels[i].pixel_error_px;
      c.switch_distance_m = parsed.levels[i].switch_distance_m;
      candidates.push_back(std::move(c));
    }
    if (in.impostor) {
      Candidate c;
      c.impostor = true;
      c.scene = &in.impostor->scene;
      c.epsilon_m = in.impostor->epsilon_m;
      c.pixel_error_px = in.impostor->pixel_error_px;
      c.switch_distance_m = std::max(in.impostor->switch_distance_m, parsed.levels[0].switch_distance_m);
      candidates.push_back(std::move(c));
    }
    for (Candidate& c : candidates) {
      c.primitives = primitives_of(*c.scene);
      for (const gltf::Mesh& mesh : c.scene->meshes) c.extent.push_back(mesh_extent(mesh));
      set_grid(c, c.switch_distance_m);
    }
  }

  // Candidate `c`'s position grids for drawing it from distance `d`: the rule of
  // PackOptions::position_error for the spatial error that projects to as many pixels at d as
  // the level's epsilon at its own switch distance, epsilon x min(1, d / switch distance) (a
  // level drawn nearer than its own switch distance gets a finer grid; its rounding stays the
  // same fraction of a pixel). Sets bits, float_error, fine and grid.
  void set_grid(Candidate& c, double d) const {
    const std::size_t meshes = c.scene->meshes.size();
    c.fine.assign(meshes, 0);
    if (!w.quantize.enabled) {
      c.bits.assign(meshes, 0);
      c.grid = {};
      c.grid.position_float = true;
      return;
    }
    const double scale = c.switch_distance_m > 0 && d < c.switch_distance_m ? d / c.switch_distance_m : 1.0;
    const double epsilon = c.epsilon_m * scale;
    c.float_error = options_.position_error * epsilon;
    std::vector<int> bits;
    for (std::size_t m = 0; m < meshes; ++m) {
      const PositionGrid g =
          position_grid(c.scene->meshes[m], epsilon, options_.position_error, options_.position_error_max);
      bits.push_back(g.bits);
      c.fine[m] = g.bits == 0 || g.bits > options_.position_bits_min;
    }
    set_bits(c, std::move(bits));
  }

  // Candidate `c` as drawn from distance `d`: set_grid(c, d) and, with
  // PackOptions::nearer_line_coverage, for a mesh level drawn from nearer than its own switch
  // distance s, the level with its blended lines' alpha for d
  // (lodmodel::line_alpha_at, s / d: the coverage of the branches they stand for at d, where they cover
  // s / d times the pixels they cover at s). Lines of other materials and every other
  // primitive are the level's. The scenes are kept here, one per level and distance.
  void draw_from(Candidate& c, double d) {
    set_grid(c, d);
    if (!options_.nearer_line_coverage || c.impostor || !(d < c.switch_distance_m)) return;
    const gltf::Scene& level = in_.levels[c.source_level];
    auto blended_lines = [&](const gltf::Primitive& p) {
      return p.mode == gltf::PrimitiveMode::kLines && p.material >= 0 && !p.colors.empty() &&
             level.materials[std::size_t(p.material)].alpha_mode == gltf::AlphaMode::kBlend;
    };
    bool any = false;
    for (const gltf::Mesh& m : level.meshes)
      any = any || std::any_of(m.primitives.begin(), m.primitives.end(), blended_lines);
    if (!any) return;
    auto [it, added] = drawn_from_.try_emplace({c.source_level, d});
    if (added) {
      it->second = level;
      const double scale = c.switch_distance_m / d;
      for (gltf::Mesh& m : it->second.meshes)
        for (gltf::Primitive& p : m.primitives)
          if (blended_lines(p))
            for (std::size_t i = 3; i < p.colors.size(); i += 4)
              p.colors[i] = float(lodmodel::line_alpha_at(p.colors[i], scale));
    }
    c.scene = &it->second;
  }

  // Candidate `c`'s position grids (one entry per mesh; 0: float) and the numbers lod.json states.
  void set_bits(Candidate& c, std::vector<int> bits) const {
    c.bits = std::move(bits);
    c.grid = {};
    for (std::size_t m = 0; m < c.bits.size(); ++m) {
      c.grid.position_bits = std::max(c.grid.position_bits, c.bits[m]);
      if (c.bits[m] > 0) {
        c.grid.position_error_m = std::max(c.grid.position_error_m, grid_error(c.extent[m], c.bits[m]));
      } else {
        c.grid.position_float = true;
        // Float positions: exact, or within position_error x epsilon through the EXPONENTIAL filter.
        if (w.meshopt) c.grid.position_error_m = std::max(c.grid.position_error_m, c.float_error);
      }
    }
  }

  // The scene `s` as a pack file: reordered for compression, the pack's asset extras, encoded
  // with each mesh's position grid (`bits`, `float_error`: one entry per mesh of `s`).
  std::string encode(gltf::Scene s, std::vector<int> bits, std::vector<double> float_error) {
    for (gltf::Image& im : s.images) im.bytes = smaller_png(im.bytes);
    w.quantize.position_bits = std::move(bits);
    w.quantize.float_position_error = std::move(float_error);
    if (options_.optimize) gltf::optimize_scene(s, gltf::OptimizeOrder::kSize);
    nlohmann::json extras = s.extras.is_object() ? s.extras : nlohmann::json::object();
    extras["sylva_stage"] = "pack";
    extras["species"] = in_.species;
    s.extras = std::move(extras);
    return gltf::encode(s, w);
  }

  // Candidate `c`'s file alone (<species>_lod<k>.glb or _impostor.glb). A mesh level's file
  // carries no extras on its nodes and meshes: its numbers (epsilon, pixel error, the switch
  // distance it is drawn from, its lod level) are lod.json's and the manifest's, and the lod
  // stage's diagnostics stay in the lod artifact. Cleared in the copy being encoded.
  std::string level_file(const Candidate& c) {
    gltf::Scene s = *c.scene;
    if (!c.impostor) {
      for (gltf::Mesh& m : s.meshes) m.extras = nullptr;
      for (gltf::Node& n : s.nodes) n.extras = nullptr;
    }
    return encode(std::move(s), c.bits, std::vector<double>(c.scene->meshes.size(), c.float_error));
  }

  ParsedChain parsed;
  std::vector<Candidate> candidates;
  gltf::WriteOptions w;

 private:
  // An embedded 8-bit RGBA PNG re-encoded at zlib level 9 (libs/image encode_png; the stages
  // write level 6), when that is smaller and decodes to the same pixels; any other image (another
  // colour type or bit depth, which decode_png would convert) as it is. Once per distinct image: the measured
  // choice encodes a level's file several times.
  const std::string& smaller_png(const std::string& bytes) {
    const auto it = smaller_png_.find(bytes);
    if (it != smaller_png_.end()) return it->second;
    std::string out = bytes;
    // PNG signature (8), IHDR length and type (8), width, height (8), bit depth, colour type.
    const bool rgba8 = bytes.size() > 26 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0 &&
                       bytes.compare(12, 4, "IHDR") == 0 && bytes[24] == 8 && bytes[25] == 6;
    if (rgba8) {
      const image::Image pixels = image::decode_png(bytes);
      const std::vector<std::uint8_t> png = image::encode_png(pixels, image::PngOptions{9});
      const std::string_view v(reinterpret_cast<const char*>(png.data()), png.size());
      if (png.size() < bytes.size() && image::decode_png(v) == pixels) out.assign(v);
    }
    return smaller_png_.emplace(bytes, std::move(out)).first->second;
  }

  const SpeciesInput& in_;
  const PackOptions& options_;
  std::map<std::string, std::string> smaller_png_;
  std::map<std::pair<std::size_t, double>, gltf::Scene> drawn_from_;  // draw_from's levels
};

std::string describe(double d) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", d);
  return buf;
}

std::string level_name(const Candidate& c) {
  return c.impostor ? std::string("the impostor") : "level " + std::to_string(c.source_level);
}

// The error model's choice (no meter): docs/stages/pack.md "Levels kept".
std::vector<LevelChoice> model_choice(const Prepared& p, const PackOptions& options) {
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
  const Candidate* impostor = p.candidates.back().impostor ? &p.candidates.back() : nullptr;
  out.reserve(p.candidates.size());
  for (const Candidate& k : p.candidates) {
    LevelChoice c;
    c.impostor = k.impostor;
    c.source_level = k.source_level;
    c.switch_distance_m = k.switch_distance_m;
    c.primitives = k.primitives;
    if (!k.impostor && k.source_level == 0) {
      c.kept = true;
    } else if (!k.impostor && impostor && c.switch_distance_m >= impostor->switch_distance_m) {
      // (impostor->switch_distance_m is at least level 0's, so this compares with impostor.json's.)
      c.reason = "the impostor is proven from " + describe(impostor->switch_distance_m) +
                 " m, before this level's switch distance " + describe(c.switch_distance_m) + " m";
    } else if (too_little(c)) {
      c.reason = saving_reason(c);
    } else {
      c.kept = true;
    }
    out.push_back(c);
    if (out.back().kept) previous = &out.back();
  }
  return out;
}

// How far the measured choice looks for an impostor that fails at its own distance: up to
// 1.25^8 = 5.96 x that distance, in steps of 1.25.
constexpr int kImpostorFartherSteps = 8;
constexpr double kImpostorFartherFactor = 1.25;

// The measured choice (docs/stages/pack.md "Levels kept"): per band start, the candidate with the
// fewest primitives whose shipped file passes the image check there.
std::vector<LevelChoice> measured_choice(Prepared& p, const PackOptions& options, LevelMeter& meter) {
  const std::vector<Candidate>& cand = p.candidates;
  const std::size_t n = cand.size();
  const bool has_impostor = cand.back().impostor;
  const std::size_t meshes = has_impostor ? n - 1 : n;
  std::vector<LevelChoice> out(n);
  for (std::size_t j = 0; j < n; ++j) {
    out[j].impostor = cand[j].impostor;
    out[j].source_level = cand[j].source_level;
    out[j].switch_distance_m = cand[j].switch_distance_m;
    out[j].primitives = cand[j].primitives;
  }
  std::vector<std::string> files(n);  // each candidate's file, encoded once, as it is measured
  // A candidate drawn from nearer than its own switch distance ships on a finer grid and with
  // its lines' alpha for that distance (draw_from): those files by candidate, grid and scene,
  // with the meter's key for each (keys from 1000000 on, in the order they are first measured:
  // deterministic).
  std::map<std::tuple<std::size_t, std::vector<int>, const gltf::Scene*>, std::pair<int, std::string>>
      nearer_files;
  int next_key = 1000000;
  auto measure = [&](std::size_t j, double d) {
    if (d < cand[j].switch_distance_m) {
      Candidate at = cand[j];
      p.draw_from(at, d);
      if (at.bits != cand[j].bits || at.scene != cand[j].scene) {
        auto [it, added] = nearer_files.try_emplace({j, at.bits, at.scene});
        if (added) it->second = {next_key++, p.level_file(at)};
        return meter.measure(it->second.first, it->second.second, d);
      }
    }
    if (files[j].empty()) files[j] = p.level_file(cand[j]);
    return meter.measure(cand[j].impostor ? -1 : int(cand[j].source_level), files[j], d);
  };
  const double keep_at_most = 1 - options.min_saving;
  auto saves = [&](std::size_t j, std::size_t c) {
    return double(cand[j].primitives) <= keep_at_most * double(cand[c].primitives);
  };
  auto saving_reason = [&](std::size_t j, std::size_t c, double b) {
    const double saved =
        cand[c].primitives == 0 ? 0 : 1 - double(cand[j].primitives) / double(cand[c].primitives);
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "saves %.3g of the primitives of %s (%llu -> %llu) at %s m, less than min_saving %.3g",
                  saved, level_name(cand[c]).c_str(), static_cast<unsigned long long>(cand[c].primitives),
                  static_cast<unsigned long long>(cand[j].primitives), describe(b).c_str(),
                  options.min_saving);
    return std::string(buf);
  };

  // Why a candidate is not kept: the latest decision about it, until its own band start has been
  // decided (what happened there is its reason).
  std::vector<char> settled(n, 0);
  auto note = [&](std::size_t j, double b, std::string why) {
    if (settled[j]) return;
    out[j].reason = std::move(why);
    settled[j] = b >= cand[j].switch_distance_m;
  };

  // A kept level whose grid (above, for the distance it is drawn from) has more than
  // position_bits_min bits (the finest levels): the coarsest grid from position_bits_min bits on
  // whose file measures as passing at distance d (where the level is drawn from) is taken, with
  // that measurement; true when one is. Never coarser than position_bits_min, nor than the grid
  // the level's epsilon asks for at d.
  auto coarsest_grid = [&](std::size_t j, double d) {
    Candidate& k = p.candidates[j];
    if (k.impostor || std::none_of(k.fine.begin(), k.fine.end(), [](char f) { return f; })) return false;
    int finest = 0;  // bits of the finest grid among the fine meshes (16 for float positions)
    for (std::size_t m = 0; m < k.bits.size(); ++m)
      if (k.fine[m]) finest = std::max(finest, k.bits[m] == 0 ? 16 : k.bits[m]);
    for (int b = options.position_bits_min; b < finest; ++b) {
      Candidate coarser = k;
      std::vector<int> bits = k.bits;
      for (std::size_t m = 0; m < bits.size(); ++m)
        if (k.fine[m] && (bits[m] == 0 || bits[m] > b)) bits[m] = b;
      p.set_bits(coarser, std::move(bits));
      const int key = 1000 + 100 * int(k.source_level) + b;  // another file of the same level
      const LevelMeter::Result r = meter.measure(key, p.level_file(coarser), d);
      if (!r.error.passed) continue;
      k = std::move(coarser);
      out[j].measured = r.error;
      return true;
    }
    return false;
  };

  // Level 0: the finest, drawn nearest; measured at its own switch distance (its coarsest grid
  // that passes there, else its own grid), and the measurement recorded.
  std::size_t c = 0;
  out[0].kept = true;
  if (!coarsest_grid(0, out[0].switch_distance_m))
    out[0].measured = measure(0, out[0].switch_distance_m).error;

  std::vector<double> starts;
  for (std::size_t j = 1; j < n; ++j) starts.push_back(cand[j].switch_distance_m);
  std::sort(starts.begin(), starts.end());
  starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
  // Candidate j at band start b (the current level c): false, with its reason noted, when it
  // saves too little over c (not measured); ...
  auto too_little = [&](std::size_t j, double b) {
    if (saves(j, c)) return false;
    note(j, b, saving_reason(j, c, b));
    return true;
  };
  // ... its measurement when it passes at b, else nullopt with the failure noted.
  auto passes = [&](std::size_t j, double b) -> std::optional<MeasuredError> {
    const LevelMeter::Result r = measure(j, b);
    if (r.error.passed) return r.error;
    note(j, b, "fails at " + describe(b) + " m: " + r.failure);
    return std::nullopt;
  };

  for (const double b : starts) {
    if (cand[c].impostor) break;  // nothing has fewer primitives
    if (!(b > out[c].switch_distance_m)) continue;
    std::optional<std::size_t> best, mesh_best;
    MeasuredError best_error;
    // The impostor first: when it passes, no mesh level has fewer primitives.
    if (has_impostor) {
      const std::size_t imp = n - 1;
      const std::optional<MeasuredError> e = too_little(imp, b) ? std::nullopt : passes(imp, b);
      if (e) {
        best = imp;
        best_error = *e;
        for (std::size_t j = c + 1; j < meshes; ++j)
          note(j, b,
               "the impostor (" + std::to_string(cand[imp].primitives) + " primitives) passes from " +
                   describe(b) + " m");
      }
    }
    // The band's own mesh level (when it is coarser than the current one; the impostor's band
    // has none: the first level coarser than the current one) and the coarser ones, finest first,
    // up to the first that fails: a coarser level of the chain has a larger epsilon, so the
    // levels after a failure are not measured.
    std::size_t from = c + 1;
    for (std::size_t j = c + 1; j < meshes; ++j)
      if (cand[j].switch_distance_m == b) from = j;
    for (std::size_t j = from; !best && j < meshes; ++j) {
      if (too_little(j, b)) continue;
      const std::optional<MeasuredError> e = passes(j, b);
      if (!e) {
        for (std::size_t k = j + 1; k < meshes; ++k)
          note(k, b,
               "not measured at " + describe(b) + " m: level " + std::to_string(j) + ", finer, fails there");
        break;
      }
      // Passes; a coarser one may pass too.
      if (mesh_best)
        note(*mesh_best, b,
             "level " + std::to_string(j) + " (" + std::to_string(cand[j].primitives) +
                 " primitives) passes at " + describe(b) + " m too");
      mesh_best = j;
      best_error = *e;
    }
    // Nothing from there on passes: the levels between the current one and the band's own,
    // coarsest first, up to the first that passes.
    for (std::size_t j = from; !best && !mesh_best && j-- > c + 1;) {
      if (too_little(j, b)) continue;
      if (const std::optional<MeasuredError> e = passes(j, b)) {
        mesh_best = j;
        best_error = *e;
      }
    }
    if (!best) best = mesh_best;
    if (best) {  // else the current level draws this band too
      LevelChoice& k = out[*best];
      k.kept = true;
      k.switch_distance_m = b;
      k.measured = best_error;
      k.reason.clear();
      c = *best;
    }
  }

  // An impostor that fails at its own distance (a far tree is a few dozen pixels, where one pixel
  // is 2 % of the check's footprint) is measured farther out, at b x 1.25^k, and kept from the
  // first of those distances where it passes: a chain with an impostor ends with it.
  if (has_impostor && !out[n - 1].kept && !cand[c].impostor && saves(n - 1, c)) {
    double d = std::max(cand[n - 1].switch_distance_m, out[c].switch_distance_m);
    for (int k = 0; k < kImpostorFartherSteps; ++k) {
      d *= kImpostorFartherFactor;
      const LevelMeter::Result r = measure(n - 1, d);
      if (!r.error.passed) continue;
      out[n - 1].kept = true;
      out[n - 1].switch_distance_m = d;
      out[n - 1].measured = r.error;
      out[n - 1].reason.clear();
      break;
    }
    if (!out[n - 1].kept)
      out[n - 1].reason = (out[n - 1].reason.empty() ? std::string("fails") : out[n - 1].reason) +
                          " (and at every distance up to " + describe(d) + " m)";
  }

  // A level kept from nearer than its own switch distance ships the grid and line alphas it was
  // measured with there (its measurement is that file's), then, as every kept level, the
  // coarsest grid search.
  for (std::size_t j = 1; j < n; ++j) {
    if (!out[j].kept) continue;
    if (out[j].switch_distance_m < cand[j].switch_distance_m)
      p.draw_from(p.candidates[j], out[j].switch_distance_m);
    coarsest_grid(j, out[j].switch_distance_m);
  }
  return out;
}

}  // namespace

std::vector<LevelChoice> select_levels(const SpeciesInput& in, const PackOptions& options,
                                       LevelMeter* meter) {
  Prepared p(in, options);
  return meter ? measured_choice(p, options, *meter) : model_choice(p, options);
}

std::vector<PackedFile> pack_species(const SpeciesInput& in, const PackOptions& options,
                                     LodDescription* description, LevelMeter* meter) {
  Prepared p(in, options);
  const ParsedChain& parsed = p.parsed;
  const std::vector<LevelChoice> choice =
      meter ? measured_choice(p, options, *meter) : model_choice(p, options);

  // The camera's tan(phi/2): from the impostor's camera, checked against the chain's coverages
  // (c_i is the coverage at level i + 1's switch distance; any unclamped one fixes tan(phi/2)).
  const double radius = bounding_radius(in.levels[0]);
  double tan_half = 0;
  for (std::size_t i = 0; i + 1 < parsed.levels.size() && tan_half == 0; ++i) {
    const double c = parsed.coverage[i];
    if (c > 0 && c < 1 && radius > 0)
      tan_half = lodmodel::coverage_tan_half_fov(radius, c, parsed.levels[i + 1].switch_distance_m);
  }
  if (in.impostor) {
    const double t = lodmodel::tan_half_fov(in.impostor->camera);
    if (tan_half > 0 && std::abs(t - tan_half) > 1e-4 * tan_half) {
      char msg[160];
      std::snprintf(msg, sizeof msg,
                    "the impostor's camera (vertical fov %.6g deg) is not the lod chain's (%.6g deg): its "
                    "switch distance is for another view",
                    lodmodel::degrees(in.impostor->camera.fov_y_rad),
                    lodmodel::degrees(2 * std::atan(tan_half)));
      throw std::invalid_argument(msg);
    }
    tan_half = t;
  }

  // The kept levels, nearest first: their candidates and numbers.
  struct Kept {
    const Candidate* candidate;
    nlohmann::json node_extras;
    std::vector<std::string> inputs;
    LodLevel level;
  };
  std::vector<Kept> kept;
  LodDescription d;
  d.species = in.species;
  d.chain = in.species + ".glb";
  std::size_t mesh_index = 0;
  for (std::size_t j = 0; j < choice.size(); ++j) {
    const LevelChoice& c = choice[j];
    if (!c.kept) {
      d.dropped.push_back({c.impostor ? "impostor" : "mesh", c.impostor ? -1 : int(c.source_level),
                           c.switch_distance_m, c.primitives, c.reason});
      continue;
    }
    const Candidate& cand = p.candidates[j];
    Kept k;
    k.candidate = &cand;
    LodLevel& l = k.level;
    l = cand.grid;
    if (c.impostor) {
      const ImpostorLevelInput& im = *in.impostor;
      k.inputs = im.inputs;
      l.file = in.species + "_impostor.glb";
      l.kind = "impostor";
      l.impostor_kind = im.kind;
      l.source_level = -1;
      k.node_extras = lodchain::impostor_level_extras(kept.size(), im.kind, im.epsilon_m, im.pixel_error_px,
                                                      c.switch_distance_m);
    } else {
      const ChainLevel& cl = parsed.levels[c.source_level];
      k.inputs = c.source_level < in.level_inputs.size() ? in.level_inputs[c.source_level]
                                                         : std::vector<std::string>{};
      l.file = in.species + "_lod" + std::to_string(mesh_index++) + ".glb";
      l.source_level = int(c.source_level);
      k.node_extras = lodchain::level_number_extras(cl.node->extras, c.switch_distance_m);
    }
    l.epsilon_m = cand.epsilon_m;
    l.pixel_error_px = cand.pixel_error_px;
    l.switch_distance_m = c.switch_distance_m;
    count_primitives(*cand.scene, l);
    l.primitives = c.primitives;
    l.measured = c.measured;
    kept.push_back(std::move(k));
  }

  // Screen coverage of kept level k: the coverage at the next kept level's switch distance. A
  // mesh level j drawn from its own switch distance: the lod chain's value c_{j-1} (the coverage
  // there, as the lod stage computed it); the impostor, or a mesh level the measured choice draws
  // from another distance: computed with the chain's camera.
  for (std::size_t k = 0; k < kept.size(); ++k) {
    double c = 0;
    if (k + 1 < kept.size()) {
      const Kept& next = kept[k + 1];
      const bool own = next.level.kind != "impostor" &&
                       next.level.switch_distance_m ==
                           parsed.levels[std::size_t(next.level.source_level)].switch_distance_m;
      c = own ? parsed.coverage[std::size_t(next.level.source_level) - 1]
              : lodmodel::screen_coverage(tan_half, radius, next.level.switch_distance_m);
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
  std::vector<double> coverage;
  for (Kept& k : kept) {
    const Candidate& cand = *k.candidate;
    const std::size_t first_mesh = chain.meshes.size(), first_node = chain.nodes.size();
    const std::vector<int> roots = gltf::append_scene(chain, *cand.scene);
    if (roots.size() != 1)
      throw std::invalid_argument(k.level.file + ": the level's scene has " + std::to_string(roots.size()) +
                                  " root nodes, expected 1");
    if (!cand.impostor) trim_level_extras(chain, first_node, first_mesh);
    gltf::Node& n = chain.nodes[std::size_t(roots[0])];
    n.extras = k.node_extras;
    n.extensions = nullptr;
    level_nodes.push_back(roots[0]);
    for (std::size_t m = first_mesh; m < chain.meshes.size(); ++m) {
      chain_bits.push_back(cand.bits[m - first_mesh]);
      chain_float_error.push_back(cand.float_error);
    }
    coverage.push_back(k.level.screen_coverage);
  }
  chain.roots = {level_nodes[0]};
  gltf::Node& root = chain.nodes[std::size_t(level_nodes[0])];
  lodchain::link_levels(root.extras, root.extensions, level_nodes, coverage);
  std::vector<std::string> chain_inputs = in.chain_inputs;
  if (in.impostor)
    chain_inputs.insert(chain_inputs.end(), in.impostor->inputs.begin(), in.impostor->inputs.end());

  std::vector<PackedFile> out;
  out.push_back({d.chain, p.encode(std::move(chain), chain_bits, chain_float_error), chain_inputs});
  for (Kept& k : kept) {
    std::string bytes = p.level_file(*k.candidate);
    k.level.bytes = bytes.size();
    out.push_back({k.level.file, std::move(bytes), k.inputs});
    d.levels.push_back(k.level);
  }
  out.push_back({in.species + ".lod.json", write_lod_json(d), chain_inputs});
  if (description) *description = std::move(d);
  return out;
}

}  // namespace sylva::pack
