#include "stages/impostor/impostor_info.h"

namespace sylva {

namespace {
// Bump whenever the bytes of any output can change (maps, impostor.json, impostor.glb).
constexpr int kVersion = 6;  // 6: packed opaque layer (bake_layers.h), nearest mip level of textures
}  // namespace

StageInfo impostor_stage_info() {
  StageInfo info;
  info.name = "impostor";
  info.version = kVersion;
  info.summary =
      "billboards and (hemi-)octahedral impostor atlases baked headlessly (colour+alpha, normal+depth)";
  info.output_type = "impostor";
  info.inputs = {{"mesh", "lod"}, 1, 1, "one mesh (tree.glb) or lod chain (lod.json and its levels)"};
  info.params = {
      Param::choice("kind", {"hemi_octahedral", "octahedral", "billboards"}, "hemi_octahedral")
          .describe("hemi_octahedral (views from above the horizon), octahedral (every view) or billboards"),
      Param::integer("frames", 16)
          .range(2, 64)
          .describe("octahedral kinds: frames per atlas side N (N x N frames)"),
      Param::integer("frame_px", 256).range(16, 4096).describe("texels per frame side"),
      Param::integer("mip_levels", 4)
          .range(0, 10)
          .describe("mip levels kept free of bleeding: padding of 2^mip_levels texels in every frame"),
      Param::integer("cards", 8).range(3, 64).describe("billboards: vertical cards around the trunk axis"),
      Param::boolean("top_card", true).describe("billboards: add the horizontal card seen from above"),
      Param::integer("cutout_vertices", 8).range(4, 8).describe("vertices of each card's cutout polygon"),
      Param::integer("msaa", 1).range(1, 16).describe(
          "coverage samples per atlas texel (llvmpipe: at most 4); 1 suffices: a texel is <= delta px"),
      Param::choice("glb_alpha", {"blend", "mask"}, "blend")
          .describe("impostor.glb's alphaMode: blend (coverage kept at every mip level) or mask"),
      Param::real("alpha_cutoff", 0.5)
          .range(0.0, 1.0)
          .describe("impostor.glb's MASK cutoff on coverage (glb_alpha: mask)"),
      Param::object(
          "camera",
          {Param::real("fov_y_deg", 45.0).range(1, 179).describe("vertical field of view phi (deg)"),
           Param::integer("height_px", 1080).range(1, 65536).describe("image height H (px)")}),
      Param::real("pixel_error", 0.5)
          .range(0.01, 100)
          .describe("permitted pixel error delta (px) of the switch distance"),
      Param::real("switch_distance_m", 0.0)
          .range(0.0, 1e7)
          .describe(
              "the switch distance impostor.json records (m); 0: the error model's. Set it to what "
              "`sylva impostorcheck --search-distance` proves: impostorcheck then checks it at every run"),
  };
  return info;
}

}  // namespace sylva
