// The impostor stage's core: a scene in, an impostor out (maps, impostor.json's content,
// impostor.glb). Every step is plain data except the draw calls, which go through
// render::ImpostorRenderer (tests may pass a fake).
//
//  1. measure the source (bounds, bounding sphere about the box centre, axis radius);
//  2. plan the atlas (layout.h): views and cards;
//  3. bake every view (libs/render, headless GL), lines as wide as the pixels their alpha was
//     made for (below);
//  4. dilate colour and normal into the uncovered texels near the tree (dilate.h);
//  5. billboards: lift the top card to the coverage-weighted mean height seen from above;
//  6. fit every card's cutout polygon (cutout.h) and light it with its frame's mean normal;
//  7. the error terms and the switch distance (libs/impostor/error_model.h);
//  8. impostor.glb (impostor_gltf.h): its cards are unlit and show the colour map lit the way
//     the verifier and the reference shader light the tree (libs/render Lighting), so every
//     viewer shows what sylva verifies; the atlas itself stays relightable (albedo + normal).
//
// Lines. A LOD level's semi-transparent lines carry as alpha the coverage of a branch in a pixel
// of size s = epsilon / delta (the level's switch distance; docs/stages/lod.md "Line alpha"). A
// line drawn w texels wide with that alpha covers alpha * w * t metres across, so the baker draws
// them w = s / t texels wide, or, when s < t, one texel wide with alpha * s / t: a branch keeps
// its width in the atlas.
#pragma once

#include <string>

#include "libs/image/image.h"
#include "libs/impostor/impostor_json.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/scene.h"
#include "stages/impostor/impostor_gltf.h"
#include "stages/impostor/layout.h"
#include "stages/impostor/source.h"

namespace sylva::impostor {

struct BakeParams {
  LayoutParams layout;
  int cutout_vertices = 8;       // 4..8 per card
  int msaa = 1;                  // coverage samples per texel
  int threads = 2;               // GL contexts baking rows side by side (the bytes do not depend on it)
  GlbAlpha glb_alpha;            // impostor.glb's alpha mode (impostor_gltf.h)
  lodmodel::Camera camera;       // the error model's camera ...
  double pixel_error = 0.5;      // ... and delta
  double switch_distance_m = 0;  // > 0: recorded instead of the error model's (a proven distance)
};

struct BakeOutput {
  ImpostorInfo info;  // map names are the stage's file names
  image::Image color, normal_depth;
  std::string glb;
  double cutout_fill = 1;  // mean area of the cards' polygons over their frames
};

// Throws std::invalid_argument for parameters that give no atlas, render::RenderError when
// drawing fails.
BakeOutput bake_impostor(render::ImpostorRenderer& renderer, const render::Scene& scene,
                         const BakeParams& params, const SourceDesc& source);

}  // namespace sylva::impostor
