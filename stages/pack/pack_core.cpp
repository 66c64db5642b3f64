// Issue 14 "The chain per species" and "Compression and size", for the mesh levels the lod
// stage proved (each level's epsilon, delta and switch distance come from its lod.gltf node).
// pack_species reads as its steps: prepare the candidates, choose the levels, check the camera,
// describe the kept levels, assemble the chain, encode every file.
#include "stages/pack/pack_core.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "libs/gltf/compose.h"
#include "libs/lodchain/chain_gltf.h"
#include "libs/lodmodel/lod_model.h"
#include "libs/pack/lod_json.h"
#include "stages/pack/candidates.h"
#include "stages/pack/chain_levels.h"
#include "stages/pack/level_choice.h"

namespace sylva::pack {

namespace {

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

// The camera's tan(phi/2): from the impostor's camera, checked against the chain's coverages
// (c_i is the coverage at level i + 1's switch distance; any unclamped one fixes tan(phi/2)).
// Throws std::invalid_argument when the impostor's camera is not the chain's.
double camera_tan_half(const SpeciesInput& in, const ParsedChain& parsed, double radius) {
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
  return tan_half;
}

// A kept level, nearest first: its candidate, its chain node's extras, the input files its own
// file is made from, and what lod.json states about it.
struct Kept {
  const Candidate* candidate;
  nlohmann::json node_extras;
  std::vector<std::string> inputs;
  LodLevel level;
};

// The kept levels of `choice`, nearest first, with their file names (mesh levels numbered in
// chain order) and numbers; the dropped ones are listed in `d.dropped`.
std::vector<Kept> kept_levels(const SpeciesInput& in, const Prepared& p,
                              const std::vector<LevelChoice>& choice, LodDescription& d) {
  const ParsedChain& parsed = p.parsed;
  std::vector<Kept> kept;
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
  return kept;
}

// Screen coverage of kept level k: the coverage at the next kept level's switch distance. A
// mesh level j drawn from its own switch distance: the lod chain's value c_{j-1} (the coverage
// there, as the lod stage computed it); the impostor, or a mesh level the measured choice draws
// from another distance: computed with the chain's camera.
void set_screen_coverage(std::vector<Kept>& kept, const ParsedChain& parsed, double tan_half, double radius) {
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
}

// The chain file's scene and the position grid of each of its meshes.
struct ChainScene {
  gltf::Scene scene;
  std::vector<int> bits;
  std::vector<double> float_error;
};

// The chain: every kept level's scene appended (images and materials shared), one node per
// level; the first is the scene's root with MSFT_lod naming the others. Throws
// std::invalid_argument for a level scene without exactly one root node.
ChainScene assemble_chain(const SpeciesInput& in, const std::vector<Kept>& kept) {
  ChainScene out;
  gltf::Scene& chain = out.scene;
  chain.generator = in.chain.generator;
  chain.extras = in.chain.extras;
  std::vector<int> level_nodes;
  std::vector<double> coverage;
  for (const Kept& k : kept) {
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
      out.bits.push_back(cand.bits[m - first_mesh]);
      out.float_error.push_back(cand.float_error);
    }
    coverage.push_back(k.level.screen_coverage);
  }
  chain.roots = {level_nodes[0]};
  gltf::Node& root = chain.nodes[std::size_t(level_nodes[0])];
  lodchain::link_levels(root.extras, root.extensions, level_nodes, coverage);
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

  const double radius = bounding_radius(in.levels[0]);
  const double tan_half = camera_tan_half(in, parsed, radius);

  LodDescription d;
  d.species = in.species;
  d.chain = in.species + ".glb";
  std::vector<Kept> kept = kept_levels(in, p, choice, d);
  set_screen_coverage(kept, parsed, tan_half, radius);
  ChainScene chain = assemble_chain(in, kept);
  std::vector<std::string> chain_inputs = in.chain_inputs;
  if (in.impostor)
    chain_inputs.insert(chain_inputs.end(), in.impostor->inputs.begin(), in.impostor->inputs.end());

  std::vector<PackedFile> out;
  out.push_back({d.chain, p.encode(std::move(chain.scene), chain.bits, chain.float_error), chain_inputs});
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
