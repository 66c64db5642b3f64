// lod.json: the summary of a `lod` artifact's chain, for every program that reads one. The one
// reader and writer of the format (docs/formats.md, docs/stages/lod.md "Outputs"): the lod stage
// writes it; the impostor, forest and pack stages, `sylva lodcheck` and `sylva impostorcheck`
// read it through parse_lod_chain / read_lod_chain. The artifact's other files are named below;
// their glTF metadata (level extras, MSFT_lod) is chain_gltf.h's.
//
// Contract: write_lod_chain(chain) gives deterministic bytes: nlohmann::json's sorted key order,
// doubles printed shortest round-trip, `dump(2)` plus a newline (the bytes the lod stage wrote
// before this library existed, byte for byte). parse_lod_chain(write_lod_chain(x)) == x for
// finite numbers. parse_lod_chain checks every field's presence, type and range and throws
// LodChainFormatError("<source>: error: <what>") on the first problem; it never crashes on bad
// input. Optional fields are std::optional exactly where the writer leaves a key out
// (ribbons_file, cards) or writes null (coverage_switch_distance_m, cards.coverage_drift).
//
// Units: metres (`_m`), pixels (`_px`), degrees (`_deg`); glTF object space of the level files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/lodmodel/lod_model.h"

namespace sylva::lodchain {

// The lod artifact's files (docs/stages/lod.md "Outputs"): their names, here only.
inline constexpr const char* kSummaryFile = "lod.json";      // this format
inline constexpr const char* kChainFile = "lod.gltf";        // the MSFT_lod chain of every level
inline constexpr const char* kFullDetailFile = "full.glb";   // the full-detail model
inline constexpr const char* kLeafImageFile = "leaves.png";  // the leaf atlas the levels share
std::string level_name(std::size_t i);    // "lod<i>": level i's node and mesh in the glTF files
std::string level_file(std::size_t i);    // "lod<i>.gltf": level i alone
std::string level_bin(std::size_t i);     // "lod<i>.bin": level i's buffer (lod.gltf's buffer i too)
std::string ribbons_file(std::size_t i);  // "lod<i>_ribbons.gltf": level i with ribbons for lines
std::string ribbons_bin(std::size_t i);   // "lod<i>_ribbons.bin": the ribbons' buffer

class LodChainFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The input tree's element counts.
struct SourceCounts {
  std::uint64_t branches = 0, leaves = 0, needles = 0;
  // An imported tree's model triangles; > 0 exactly when level 0 (and full.glb) is the imported
  // model itself (docs/stages/lod.md "Imported trees"). Written only when > 0.
  std::uint64_t model_triangles = 0;
  friend bool operator==(const SourceCounts&, const SourceCounts&) = default;
};

// A level's primitives (docs/stages/lod.md: quads counted as quads, `lines` in segments).
struct LevelCounts {
  std::uint64_t quads = 0, triangles = 0, lines = 0, leaves = 0, needle_lines = 0, needle_quads = 0,
                internodes = 0, branches = 0;
  friend bool operator==(const LevelCounts&, const LevelCounts&) = default;
};

// How a level's cards were chosen (written when the chain has card_cluster_px > 0).
struct CardChoice {
  std::string from = "fsa";              // "clusters" or "fsa"
  std::uint64_t cluster_cut = 0;         // cards of the clusters' cut (0 where not built)
  std::uint64_t clusters_split = 0;      // clusters split by card_max_scale
  std::optional<double> coverage_drift;  // signed; null where not measured
  bool rejected = false;                 // refused by card_coverage_check
  friend bool operator==(const CardChoice&, const CardChoice&) = default;
};

struct Level {
  std::uint64_t sylva_lod_level = 0;  // the level's index in `levels` (checked)
  double epsilon_m = 0;               // spatial error, > 0, strictly increasing along the chain
  double pixel_error_px = 0;          // delta the level was built for, > 0
  double switch_distance_m = 0;       // distance from which the level is valid, >= 0
  double e1_m = 0, e2_m = 0, e3_m = 0, e4_m = 0, e5_m = 0;   // budgets E1..E5, >= 0
  double line_alpha = 1, line_alpha_eq12 = 1;                // branch lines: drawn, eq. 12; [0, 1]
  double needle_line_alpha = 1, needle_line_alpha_eq12 = 1;  // needle lines: the same; [0, 1]
  double max_polygon_error_m = 0;                            // >= 0
  LevelCounts counts;
  std::string file;                         // "lod<i>.gltf", not empty
  std::optional<std::string> ribbons_file;  // "lod<i>_ribbons.gltf" when written (not empty)
  double screen_coverage = 0;               // MSFT_screencoverage value, [0, 1]
  // Where a coverage-driven loader leaves the level (>= 0); null for the last (coverage 0).
  std::optional<double> coverage_switch_distance_m;
  std::optional<CardChoice> cards;  // with card_cluster_px > 0
  friend bool operator==(const Level&, const Level&) = default;
};

struct LodChain {
  std::string tree;  // the tree's name
  // `camera`: the camera the chain's errors and switch distances are for, as the file states it
  // (degrees, so that a file rewrites byte for byte; camera() is the model's).
  double camera_fov_y_deg = 45;  // vertical field of view, in (0, 180)
  int camera_height_px = 1080;   // image height, >= 1
  double pixel_error_px = 0.5;   // delta, > 0
  double tree_height_m = 0;      // y extent of the skeleton, >= 0
  double bounding_radius_m = 0;  // half the diagonal of level 0's box, >= 0
  SourceCounts source;
  std::string chain_file = kChainFile;  // the MSFT_lod chain, not empty
  std::vector<Level> levels;            // finest first; 1..8 of them
  // The camera of the error model (libs/lodmodel): lodmodel::camera_from_degrees of the above.
  lodmodel::Camera camera() const;
  friend bool operator==(const LodChain&, const LodChain&) = default;
};

std::string write_lod_chain(const LodChain& chain);
LodChain parse_lod_chain(const std::string& text, const std::string& source_name);
LodChain read_lod_chain(const std::string& path);  // also throws for an unreadable file

}  // namespace sylva::lodchain
