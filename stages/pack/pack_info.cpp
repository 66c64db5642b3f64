#include "stages/pack/pack_info.h"

namespace sylva {

StageInfo pack_stage_info() {
  StageInfo info;
  info.name = "pack";
  info.version = 1;
  info.summary =
      "game-ready asset pack: per species an MSFT_lod GLB, one GLB per level and lod.json, "
      "compressed; manifest.json";
  info.output_type = "pack";
  info.outputs = {"*.glb", "*.lod.json", "manifest.json"};
  info.inputs = {{"lod"}, 1, -1, "one lod chain per species, in `species` order"};
  info.params = {
      Param::string_list("species")
          .items(1, std::nullopt)
          .describe("the species name of each input, in `needs` order ([a-z0-9_-]+, unique): file names"),
      Param::choice("compression", {"none", "meshopt", "draco"}, "meshopt")
          .describe(
              "geometry compression: EXT_meshopt_compression (lossless), KHR_draco_mesh_compression or none"),
      Param::boolean("optimize", true)
          .describe("reorder every mesh for vertex cache, overdraw and vertex fetch (meshoptimizer)"),
  };
  return info;
}

}  // namespace sylva
