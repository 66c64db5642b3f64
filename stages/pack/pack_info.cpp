#include "stages/pack/pack_info.h"

namespace sylva {

namespace {

// Every parameter of the stage with its default, range and description, in the order the CLI
// lists them (docs/stages/pack.md explains each).
std::vector<ParamSpec> pack_params() {
  return {
      Param::string_list("species", Value::List{})
          .describe("the species name of each lod input, in `needs` order ([a-z0-9_-]+, unique): file names"),
      Param::choice("compression", {"none", "meshopt", "draco"}, "meshopt")
          .describe("geometry compression: EXT_meshopt_compression, KHR_draco_mesh_compression or none"),
      Param::boolean("optimize", true)
          .describe(
              "reorder every mesh for compression (meshoptimizer's strip-friendly vertex cache order, as "
              "gltfpack -cc) and vertex fetch"),
      Param::boolean("quantize", true)
          .describe("KHR_mesh_quantization: integer positions (grid from each level's epsilon), octahedral "
                    "normals, uvs at texcoord_bits (not with draco)"),
      Param::real("position_error", 0.25)
          .range(0.001, 1)
          .describe("largest position rounding error, as a fraction of each level's epsilon_m"),
      Param::real("position_error_max", 1.0)
          .range(0.001, 1)
          .describe("a level whose position_error grid would need more than 16 bits gets 16 bits when they "
                    "round within this fraction of its epsilon_m (else float positions)"),
      Param::integer("normal_bits", 8).range(4, 16).describe("bits per octahedral normal component"),
      Param::real("min_saving", 0.1)
          .range(0, 0.99)
          .describe("keep a level only if it saves at least this fraction of the primitives of the level "
                    "kept before it"),
      Param::choice("forest_compression", {"none", "meshopt"}, "meshopt")
          .describe(
              "the forests' .gltf tiles and level files: EXT_meshopt_compression over their shared .bin "
              "buffers (lossless), or copied as the forest stage wrote them"),
      Param::string_list("forests", Value::List{})
          .describe("the name of each forest input, in `needs` order ([a-z0-9_-]+): the manifest's forests"),
      Param::integer("position_bits_min", 14)
          .range(1, 16)
          .describe(
              "with measure: a level whose grid has more bits gets the coarsest grid from this many bits "
              "on that measures as passing at its switch distance"),
      Param::boolean("nearer_line_coverage", false)
          .describe(
              "with measure: a level drawn from nearer than its own switch distance draws its blended lines "
              "with their coverage there (alpha for c x s / b); more bytes for line-heavy levels"),
      Param::boolean("measure", true)
          .describe("choose each band's level by image error measured with lodcheck's renderer and views "
                    "against the lod input's full.glb (false: the error model's switch distances)"),
      Param::real_list("measure_azimuths_deg", Value::List{0.0, 90.0})
          .range(-360, 360)
          .items(1, std::nullopt)
          .describe("the views of the measurement: azimuths in degrees (lodcheck's default 0 and 90)"),
      Param::integer("measure_supersample", 2)
          .range(1, 4)
          .describe("render the measurement at this multiple of the chain's image height, averaged down"),
      Param::real("measure_max_failing_fraction", 0.01)
          .range(0, 1)
          .describe("a view passes while at most this fraction of the tree's pixels change coverage by more "
                    "than delta"),
      Param::real("measure_max_coverage_error", 0.15)
          .range(0, 1)
          .describe("... and the mean coverage change over the tree's pixels is at most this"),
      Param::integer("texcoord_bits", 12)
          .range(8, 16)
          .describe("bits per texture coordinate (uvs in [0, 1])"),
  };
}

}  // namespace

StageInfo pack_stage_info() {
  StageInfo info;
  info.name = "pack";
  // 8: levels chosen by measured image error (measure: true), measured numbers in lod.json and
  // the manifest (version 4); a level drawn from another band start states that switch distance.
  // 9: a level drawn from nearer than its own switch distance gets the position grid of that
  // distance (epsilon x d / switch distance), searched from position_bits_min there; an impostor
  // failing at its own distance is kept from the first farther distance (x 1.25 steps) where it
  // passes; lines keep their vertex order (smaller files).
  // 10: with nearer_line_coverage, a level drawn from nearer than its own switch distance draws
  // its blended lines with the alpha of that distance; the files' JSON prints numbers as short as their
  // floats and leaves out a primitive's default mode; a mesh level's own file carries no node or mesh extras
  // (lod.json has them); embedded PNGs re-deflated at zlib level 9 (same pixels).
  info.version = 10;
  info.summary =
      "game-ready asset pack: per species an MSFT_lod GLB (mesh levels, impostor last), one GLB per "
      "level and lod.json, compressed; forests' tiles and tileset; manifest.json";
  info.output_type = "pack";
  // The pack's own files, and a forest's (any name the forest stage writes: it is copied as is).
  info.outputs = {};
  info.inputs = {{"lod", "impostor", "forest", "pack"},
                 1,
                 -1,
                 "one lod chain per species, in `species` order; optionally one impostor per species (same "
                 "order: the chain's last level); forests (in `forests` order); other packs, merged whole"};
  info.params = pack_params();
  return info;
}

}  // namespace sylva
