// Stage `pack`'s core (issue 14; docs/stages/pack.md): one species' LOD chain, as the lod stage
// wrote it (lod.gltf with MSFT_lod over lod<i>.gltf levels), and optionally its impostor (the
// impostor stage's impostor.glb with the switch distance of impostor.json), into the files a game
// ships:
//   <species>.glb          every kept level in one file, linked by MSFT_lod + MSFT_screencoverage
//                          (three.js's MSFT_lod plugin switches by the coverages;
//                          Babylon.js reads only the ids), the impostor last;
//   <species>_lod<k>.glb   each kept mesh level alone (Blender, Godot, Unreal and Unity ignore
//                          MSFT_lod), k = 0.. in chain order;
//   <species>_impostor.glb the impostor level alone (when there is one);
//   <species>.lod.json     engine-neutral: levels, switch distances, screen coverage, sizes.
// Levels kept (select_levels), with a LevelMeter (measured choice; docs/stages/pack.md "Levels
// kept"): mesh level 0, measured at its switch distance; then at each band start (each further
// mesh level's switch distance, then the impostor's), among the candidates that save at least
// min_saving of the current level's primitives, the one with the fewest primitives whose shipped
// file passes the image check there: the impostor first; else the band's own level and the
// coarser ones, finest first, up to the first that fails; else the levels between the current
// one and the band's own, coarsest first, up to the first that passes; else the current level
// draws the band too. A kept level is drawn from the band start where it was chosen. Without a
// meter (error model): mesh level 0; every further mesh level whose switch distance lies before
// the impostor's and that saves min_saving over the level kept before it; the impostor when it
// saves min_saving over the last kept mesh level.
// Every mesh is reordered by meshoptimizer (strip-friendly vertex cache order, fetch) and compressed as
// asked; textures are the lod stage's PNGs, byte for byte. Pure over the scenes read from the
// lod files: no file system, no clock; rendering only through the LevelMeter.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "libs/gltf/scene.h"
#include "libs/lodmodel/lod_model.h"
#include "libs/pack/lod_json.h"
#include "stages/pack/position_grid.h"

namespace sylva::pack {

enum class Compression { kNone, kMeshopt, kDraco };

struct PackOptions {
  Compression compression = Compression::kMeshopt;
  bool optimize = true;
  // KHR_mesh_quantization (not with Draco, which quantises itself): each level's positions on
  // the coarsest grid whose rounding error (sqrt(3)/2 of a step) is at most position_error x the
  // level's epsilon, so the quantised level stays within a fraction of the error the lod stage
  // proved. A level that would need more than 16 bits (KHR_mesh_quantization's finest grid) gets
  // 16 bits when their rounding error is at most position_error_max x epsilon (the finest level
  // of a large tree: 16 bits over 48 m round by 0.63 mm, within its 1 mm epsilon; measured image
  // error below gltfpack's 14 bits, docs/performance.md), else it keeps float positions, with
  // meshopt through its EXPONENTIAL filter within position_error x epsilon
  // (gltf::QuantizeOptions::float_position_error). Normals octahedral with normal_bits, uvs in
  // [0, 1] with texcoord_bits (gltf::QuantizeOptions).
  bool quantize = true;
  double position_error = 0.25;     // (0, 1]
  double position_error_max = 1.0;  // [position_error, 1]
  int normal_bits = 8;              // 1..16
  int texcoord_bits = 12;           // 1..16
  // A level is kept only when it has at most (1 - min_saving) x the primitives of the level
  // kept before it; [0, 1).
  double min_saving = 0.1;
  // A level drawn from a distance d nearer than its own switch distance (the measured choice may
  // keep it from an earlier band start) gets the grid of this rule for epsilon x d / its switch
  // distance: the same fraction of a pixel at d as epsilon's grid at its own distance.
  // With a meter: a kept level whose grid (the rules above) has more than position_bits_min bits,
  // or float positions, gets the coarsest grid from position_bits_min bits on whose file measures
  // as passing where it is drawn from (else its own). 14 is gltfpack's default; [1, 16].
  int position_bits_min = 14;
  // With a meter: a level drawn from a band start b nearer than its own switch distance s draws
  // its blended lines (BLEND material, COLOR_0) with the alpha of the coverage c x s / b (capped
  // at 1) of their coverage c at s (the lod stage's three-line split), measured and shipped so.
  // Off: the lod stage's alphas (the coverage at s) wherever a level is drawn from.
  bool nearer_line_coverage = false;
};

// The impostor level: impostor.glb read back, and impostor.json's numbers (libs/impostor).
struct ImpostorLevelInput {
  gltf::Scene scene;                // impostor.glb
  std::string kind;                 // impostor.json kind ("billboards", "hemi_octahedral", ...)
  double epsilon_m = 0;             // impostor.json error.epsilon_m()
  double pixel_error_px = 0;        // delta
  double switch_distance_m = 0;     // from here on the impostor is within delta px
  lodmodel::Camera camera;          // the camera its switch distance is for
  std::vector<std::string> inputs;  // input files (impostor.json, impostor.glb)
};

// One output file and the input files it was made from (names in the lod artifact).
struct PackedFile {
  std::string name;
  std::string bytes;
  std::vector<std::string> inputs;
};

struct SpeciesInput {
  std::string species;                                 // file name stem
  gltf::Scene chain;                                   // lod.gltf
  std::vector<gltf::Scene> levels;                     // lod<i>.gltf, i = 0..n-1
  std::vector<std::vector<std::string>> level_inputs;  // input files of each level (gltf, bin, png)
  std::vector<std::string> chain_inputs;               // input files of the chain
  std::optional<ImpostorLevelInput> impostor;          // the chain's last level, when given
};

// The measured level choice's one side effect, rendering, behind an interface: the pack stage's
// RenderedLevelMeter (level_meter.h) draws with `sylva lodcheck`'s machinery
// (libs/check/view_check.h); tests give fakes.
class LevelMeter {
 public:
  struct Result {
    MeasuredError error;  // the worse view's numbers, and whether every view passed
    std::string failure;  // the first failing view's sentence ("az0: coverage of ..."), "" when passed
  };
  virtual ~LevelMeter() = default;
  // The image error of the candidate level `key` (a mesh level's lod index, or -1 for the
  // impostor; other keys name other files of a level: another position grid), whose file as
  // shipped is `glb`, seen from `distance_m`. A key always comes with the same bytes. Throws
  // std::runtime_error when it cannot measure (the stage reports it).
  virtual Result measure(int key, const std::string& glb, double distance_m) = 0;
};

// What select_levels decided for one candidate level (mesh levels in lod order, then the impostor).
struct LevelChoice {
  bool impostor = false;
  std::size_t source_level = 0;  // index into SpeciesInput::levels (mesh levels)
  double switch_distance_m = 0;  // kept: where the pack draws it from; dropped: its own
  std::uint64_t primitives = 0;  // triangles + lines + points
  bool kept = false;
  std::string reason;                     // why a level was dropped (empty when kept)
  std::optional<MeasuredError> measured;  // kept, with a meter: at switch_distance_m
};
// Throws std::invalid_argument like pack_species for a malformed chain; what the meter throws.
std::vector<LevelChoice> select_levels(const SpeciesInput& in, const PackOptions& options,
                                       LevelMeter* meter = nullptr);

// The species' files: chain GLB, kept level GLBs (nearest first, the impostor last), lod.json; in
// that order. Throws std::invalid_argument when the chain is not an MSFT_lod chain over the
// levels (its root node names n-1 others, each node holds a level with epsilon_m and
// switch_distance_m extras), or when the impostor's camera differs from the chain's (its switch
// distance would be for another view). `description`, when not null, receives what lod.json
// states (the kept levels' numbers, the dropped levels), for the manifest. With `meter` the levels
// are chosen by measured image error (select_levels) and each kept level records its measurement.
std::vector<PackedFile> pack_species(const SpeciesInput& in, const PackOptions& options,
                                     LodDescription* description = nullptr, LevelMeter* meter = nullptr);

}  // namespace sylva::pack
