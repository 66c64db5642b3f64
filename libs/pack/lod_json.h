// <species>.lod.json (issue 14; docs/stages/pack.md "Layout"): the engine-neutral description
// of a species' shipped LOD chain, for engines that do not read MSFT_lod. One writer, here.
//
//   {"format": "sylva-pack-lod", "version": 4, "species": "oak", "chain": "oak.glb",
//    "levels": [{"file": "oak_lod0.glb", "kind": "mesh", "source_level": 0, "epsilon_m": ..,
//                "pixel_error_px": .., "switch_distance_m": .., "screen_coverage": ..,
//                "primitives": .., "triangles": .., "lines": .., "bytes": .., "position_bits": ..,
//                "position_error_m": .., "position_float": ..,
//                "measured": {"failing_fraction": .., "coverage_mean_error": .., "passed": ..}},
//               ..., {"file": "oak_impostor.glb", "kind": "impostor", "impostor_kind": "billboards",
//                     "source_level": -1, ...}],
//    "dropped": [{"kind": "mesh", "source_level": 3, "switch_distance_m": .., "primitives": ..,
//                 "reason": ".."}]}
// Nearest level first; `source_level` is the lod stage's level index (-1 for the impostor);
// `dropped` lists the candidate levels the pack did not keep, and why. Level i is proven (at most
// pixel_error_px of image error) from its switch distance on, and is drawn while the tree's bounding sphere
// covers at least screen_coverage of the screen height (MSFT_screencoverage); nearer than level 0's switch
// distance no level is proven. Canonical bytes: sorted keys, two-space indent, final newline.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sylva::pack {

// A level's image error as the pack measured it (its measured level choice): the level as shipped
// against the full-detail tree at the level's switch distance, `sylva lodcheck`'s cameras and
// verdict (libs/check/view_check.h); the worse of the views for each number.
struct MeasuredError {
  double failing_fraction = 0;     // footprint pixels whose coverage changed by more than delta (0..1)
  double coverage_mean_error = 0;  // mean coverage change over the footprint (0..1)
  bool passed = false;             // every view within the check's bounds
  friend bool operator==(const MeasuredError&, const MeasuredError&) = default;
};

struct LodLevel {
  std::string file;
  std::string kind = "mesh";  // "mesh" or "impostor"
  std::string impostor_kind;  // impostor.json kind (impostor levels only)
  int source_level = 0;       // lod stage level index, -1 for the impostor
  double epsilon_m = 0, pixel_error_px = 0, switch_distance_m = 0, screen_coverage = 0;
  std::uint64_t primitives = 0, triangles = 0, lines = 0, bytes = 0;
  // KHR_mesh_quantization of the level's positions: the grid's bits (the largest over the
  // level's meshes) and the largest rounding error in metres; position_float when some mesh
  // keeps float positions (bits 0 when all do; their error is 0 when exact, else the EXPONENTIAL
  // filter's bound).
  int position_bits = 0;
  double position_error_m = 0;
  bool position_float = false;
  std::optional<MeasuredError> measured;  // absent when the pack did not measure (measure: false)
  friend bool operator==(const LodLevel&, const LodLevel&) = default;
};

struct DroppedLevel {
  std::string kind = "mesh";
  int source_level = 0;
  double switch_distance_m = 0;
  std::uint64_t primitives = 0;
  std::string reason;
};

struct LodDescription {
  std::string species, chain;
  std::vector<LodLevel> levels;
  std::vector<DroppedLevel> dropped;
};

std::string write_lod_json(const LodDescription& d);

}  // namespace sylva::pack
