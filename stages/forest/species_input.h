// One species' inputs as the forest stage reads them (docs/stages/forest.md, "Inputs"): its lod
// artifact (lod.json through libs/lodchain, the level glTF files: their bounding boxes and LOD
// metadata, never their code) and its optional impostor artifact. Part of the adapter: reads
// through the StageContext and throws StageError naming the input.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "libs/impostor/impostor_json.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/lodmodel/lod_model.h"
#include "pipeline/stage.h"
#include "stages/forest/impostor_level.h"
#include "stages/forest/tile_gltf.h"

namespace sylva::forest {

// One species' lod artifact (and impostor artifact) as the stage reads it.
struct SpeciesInput {
  std::string node;
  lodchain::LodChain chain;  // lod.json
  std::vector<LevelSource> levels;
  std::vector<const ArtifactFile*> level_bins, images;
  Box3 bounds;
  std::vector<std::size_t> primitives;
  // The impostor level (when the species has an impostor input): its source, buffer, epsilon and
  // impostor.json's recorded switch distance with the delta and camera it is valid for.
  bool has_impostor = false;
  ImpostorLevel impostor;
  double impostor_epsilon_m = 0;
  double impostor_switch_distance_m = 0;
  double impostor_pixel_error_px = 0;
  lodmodel::Camera impostor_camera;
  // A (hemi-)octahedral impostor: its impostor.json (maps renamed to the forest's copies) and maps.
  bool octahedral = false;
  impostor::ImpostorInfo impostor_info;
  const ArtifactFile* color_map = nullptr;
  const ArtifactFile* normal_depth_map = nullptr;
  // species[i].impostor_parallax: (from_m in impostor.json's terms, steps).
  std::vector<ParallaxStep> parallax;
};

// Species `name`'s lod artifact `in`: lod.json, every level file it lists with its buffer and
// images (checked to be in the artifact), each level's primitive count and level 0's bounds.
SpeciesInput read_species(const StageContext& ctx, const InputArtifact& in, const std::string& name);

// The species' impostor artifact: impostor.json (libs/impostor's reader: its epsilon) and
// impostor.glb, which becomes the species' last level; for the (hemi-)octahedral kinds also the
// two maps, which renderers with the reference shader draw (impostor.glb is then their fallback).
void read_impostor(const StageContext& ctx, const InputArtifact& in, const std::string& name,
                   SpeciesInput& s);

}  // namespace sylva::forest
