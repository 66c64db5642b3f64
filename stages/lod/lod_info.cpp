#include "stages/lod/lod_info.h"

namespace sylva {

StageInfo lod_stage_info() {
  StageInfo info;
  info.name = "lod";
  // 2: MSFT_lod written by libs/gltf (JSON bytes changed). 3: leaves wound with their normals,
  // mesh-stage colours, screen coverage as a screen fraction, .gltf + shared .bin files, ribbons.
  // 4: merging by exponential + binary search (groups may differ). 5: line alpha per vertex
  // (COLOR_0), decimated branches' coverage carried onto their bearers' lines.
  // 6: twigs drawn by cards carry no coverage onto their bearers.
  // 7: card clusters (card_clusters.h) cut the coarse levels' cards.
  // 8: opacity-weighted card clusters (each card weighs its atlas variant's measured opacity),
  // card_coverage_check and card_max_scale.
  // 9: card_places (the cards of one placement, a crossed pair, clustered as one unit).
  // 10: full.glb, the full-detail model (the pack stage measures its levels against it).
  info.version = 10;
  info.summary = "error-metric LOD chain: Zhang branch LOD (meshes -> lines) + FSA leaf collapse";
  info.output_type = "lod";
  info.outputs = {"lod*.gltf", "lod*.bin", "lod.json", "*.png", "source*.jpg", "full.glb"};
  info.inputs = {{"tree"}, 1, 1, "one tree artifact (tree.sylt, optional leaves.png)"};
  info.params = {
      Param::object(
          "camera",
          {Param::real("fov_y_deg", 45.0).range(1, 179).describe("vertical field of view phi (deg)"),
           Param::integer("height_px", 1080).range(1, 65536).describe("image height H (px)")}),
      Param::real("pixel_error", 0.5).range(0.01, 100).describe("permitted pixel error delta (px), Zhang §3"),
      Param::integer("levels", 6).range(1, 8).describe("number of levels N (Zhang §6: N <= 8)"),
      Param::real_list("errors_m", Value::List{})
          .range(1e-6, 100)
          .items(0, 8)
          .require_increasing()
          .describe("explicit spatial error epsilon per level (m), increasing; overrides levels"),
      Param::real("min_error_m", 0.001).range(1e-6, 100).describe("epsilon of level 0 (m)"),
      Param::real("max_error_m", 0.22)
          .range(1e-6, 100)
          .describe("epsilon of the coarsest level (m), Zhang §6"),
      Param::real("e1", 0.25).range(0, 10).describe("E1 / epsilon: positional merging error phi (eq. 3)"),
      Param::real("e2", 0.25)
          .range(0, 10)
          .describe("E2 / epsilon: radius/frame merging error varphi (eq. 3)"),
      Param::real("e3", 1.0).range(0, 10).describe(
          "E3 / epsilon: polygonisation error, rho = E3/R (eq. 9-12)"),
      Param::real("e4", 0.5).range(0, 10).describe(
          "E4 / epsilon: topology (accumulated bearer distance, §5.3)"),
      Param::real("e5", 1.0).range(0, 10).describe("E5 / epsilon: needle merging and leaf collapse error"),
      Param::real("torsion_limit_deg", 60.0)
          .range(0, 360)
          .describe("torsion limit Gamma of one merged internode (deg)"),
      Param::integer("max_edges", 12).range(3, 64).describe("H: most edges of an end polygon (eq. 9)"),
      Param::boolean("topology", true).describe("topology simplification by E4 (§5.3)"),
      Param::boolean("foliage", true).describe("leaf collapse (FSA) and needle merging (E5)"),
      Param::real("card_cluster_px", 0.0)
          .range(0, 16)
          .describe("kappa: card clusters' spread (px at the level's switch distance) for the coarse "
                    "levels' card cut; 0 = FSA only"),
      Param::real("card_size_px", 1.5)
          .range(0.01, 16)
          .describe("sigma: only cards of half-diagonal <= sigma px at the level's switch distance are "
                    "clustered"),
      Param::real("card_coverage_check", 0.0)
          .range(0, 1)
          .describe("a card-cluster cut is used only when its drawn coverage drifts by at most this "
                    "fraction from FSA's cut of the level (card_coverage.h); 0 = no check"),
      Param::real("card_max_scale", 0.0)
          .range(0, 100)
          .describe("largest linear scale of a card cluster's survivor; larger clusters are split; "
                    "0 = no cap"),
      Param::boolean("card_places", false)
          .describe("card clusters: the cards of one placement (a crossed pair: same base, direction "
                    "and size) are clustered as one unit and survive as a crossed pair"),
      Param::boolean("ribbons", false)
          .describe("also write lod<i>_ribbons.gltf: line levels as three-sided ribbons for clients "
                    "without LINES"),
  };
  return info;
}

}  // namespace sylva
