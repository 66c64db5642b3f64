// The pack's candidate levels (docs/stages/pack.md, "Levels kept" and "Compression and size"):
// every mesh level of the chain, then the impostor, each with the numbers the lod stage or
// impostor.json gave it and the position grid it ships with, and the writer that encodes a
// candidate as the file the pack ships. Both level choices measure or compare candidates;
// pack_species encodes the kept ones. Pure: no file system, no clock.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "libs/gltf/scene.h"
#include "libs/gltf/writer.h"
#include "libs/pack/lod_json.h"
#include "stages/pack/chain_levels.h"
#include "stages/pack/pack_core.h"

namespace sylva::pack {

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
// choice (which measures the files as shipped) and pack_species need. Holds references to `in`
// and `options`, which must outlive it; candidates' scenes point into `in` or into this object.
class Prepared {
 public:
  // Throws std::invalid_argument for a malformed chain (parse_chain) or a min_saving outside [0, 1).
  Prepared(const SpeciesInput& in, const PackOptions& options);

  // Candidate `c`'s position grids for drawing it from distance `d`: the rule of
  // PackOptions::position_error for the spatial error that projects to as many pixels at d as
  // the level's epsilon at its own switch distance, epsilon x min(1, d / switch distance) (a
  // level drawn nearer than its own switch distance gets a finer grid; its rounding stays the
  // same fraction of a pixel). Sets bits, float_error, fine and grid.
  void set_grid(Candidate& c, double d) const;

  // Candidate `c` as drawn from distance `d`: set_grid(c, d) and, with
  // PackOptions::nearer_line_coverage, for a mesh level drawn from nearer than its own switch
  // distance s, the level with its blended lines' alpha for d
  // (lodmodel::line_alpha_at, s / d: the coverage of the branches they stand for at d, where they cover
  // s / d times the pixels they cover at s). Lines of other materials and every other
  // primitive are the level's. The scenes are kept here, one per level and distance.
  void draw_from(Candidate& c, double d);

  // Candidate `c`'s position grids (one entry per mesh; 0: float) and the numbers lod.json states.
  void set_bits(Candidate& c, std::vector<int> bits) const;

  // The scene `s` as a pack file: reordered for compression, the pack's asset extras, encoded
  // with each mesh's position grid (`bits`, `float_error`: one entry per mesh of `s`).
  std::string encode(gltf::Scene s, std::vector<int> bits, std::vector<double> float_error);

  // Candidate `c`'s file alone (<species>_lod<k>.glb or _impostor.glb). A mesh level's file
  // carries no extras on its nodes and meshes: its numbers (epsilon, pixel error, the switch
  // distance it is drawn from, its lod level) are lod.json's and the manifest's, and the lod
  // stage's diagnostics stay in the lod artifact. Cleared in the copy being encoded.
  std::string level_file(const Candidate& c);

  ParsedChain parsed;
  std::vector<Candidate> candidates;
  gltf::WriteOptions w;

 private:
  // An embedded 8-bit RGBA PNG re-encoded at zlib level 9 (libs/image encode_png; the stages
  // write level 6), when that is smaller and decodes to the same pixels; any other image (another
  // colour type or bit depth) as it is. Once per distinct image.
  const std::string& smaller_png(const std::string& bytes);

  const SpeciesInput& in_;
  const PackOptions& options_;
  std::map<std::string, std::string> smaller_png_;
  std::map<std::pair<std::size_t, double>, gltf::Scene> drawn_from_;  // draw_from's levels
};

// A distance as the reasons state it ("%.6g").
std::string describe(double d);

// "level <i>" or "the impostor", as the reasons name a candidate.
std::string level_name(const Candidate& c);

}  // namespace sylva::pack
