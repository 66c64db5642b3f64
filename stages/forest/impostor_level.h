// A species' impostor as the last level of its chain in the forest (issue 13 "Output": "one file
// per LOD level of the species ..., the impostor level included"): the impostor artifact's
// impostor.glb (its cards, one embedded image; docs/stages/impostor.md) split into a .gltf and
// its .bin, so that the forest's tile files can instance it by reference like every other level,
// and its switch distance in the species' chain's terms (docs/lod-model.md): the one
// impostor.json records (its `switch_distance_m`: a proven distance when the recipe set one, else
// the error model's), never one recomputed from its epsilon.
#pragma once

#include <string>

#include "libs/lodmodel/lod_model.h"
#include "stages/forest/tile_gltf.h"

namespace sylva::forest {

struct ImpostorLevel {
  LevelSource source;  // the GLB's JSON (buffer 0 gets bin_name as its uri when written)
  std::string bin;     // buffer 0's bytes (exactly its byteLength)
};

// Splits a GLB (glTF 2.0 binary container: a JSON chunk, then one BIN chunk) into its JSON and its
// buffer; `name` is the species name (the copies are "<name>_impostor.bin", images stay in the
// buffer). Throws std::invalid_argument("<what>: ...") when the bytes are not such a GLB or its
// JSON does not describe one buffer and one mesh.
ImpostorLevel impostor_level_source(const std::string& glb, const std::string& name, const std::string& what);

// The impostor level's switch distance in the chain's terms: impostor.json's recorded distance
// `recorded_m`, valid for the impostor's own camera and delta, moved to the distance where the
// chain's camera and delta allow the same error: recorded_m x lodmodel::distance_scale (= (delta_i
// s_i(1)) / (delta_c s_c(1))). Exactly `recorded_m` when the two agree (within 1e-9 relative), as
// they do when the impostor stage keeps its defaults and the chain was built for the same camera.
double impostor_switch_distance_m(double recorded_m, const lodmodel::Camera& impostor_camera,
                                  double impostor_pixel_error_px, const lodmodel::Camera& chain_camera,
                                  double chain_pixel_error_px);

}  // namespace sylva::forest
