// Where every frame of an impostor atlas comes from and where it goes: the views the baker draws
// (libs/render/impostor_renderer.h BakeView) and the cards impostor.glb is made of.
//
// Sources: octahedral impostors (Brucks 2018) on the grid of libs/impostor/octahedral.h, frames
// fitted to the bounding sphere so no view clips the tree; SpeedTree-style billboards (a ring of
// vertical cards around the trunk axis, 360/K degrees apart, plus a horizontal card). The
// padding of 2^mip_levels texels keeps the sphere's disc that far from every frame's border, so
// bilinear sampling at mip level <= mip_levels never reads a neighbouring frame
// (docs/stages/impostor.md, "Atlas layout").
#pragma once

#include <string>
#include <vector>

#include "libs/impostor/impostor_json.h"
#include "libs/render/impostor_renderer.h"
#include "libs/render/scene.h"

namespace sylva::impostor {

struct LayoutParams {
  Kind kind = Kind::kHemiOctahedral;
  int frames_per_side = 16;  // octahedral kinds: N (2..64)
  int frame_px = 256;        // texels per frame side (>= 16)
  int mip_levels = 4;        // padding = 2^mip_levels texels, < frame_px / 4
  int cards = 8;             // billboards: vertical cards (3..64)
  bool top_card = true;      // billboards: the horizontal card
};

// The extent of what is baked, in the source's object space.
struct SourceGeometry {
  Vec3d bounds_min{}, bounds_max{};
  Vec3d center{};                // the box centre: the sphere's centre and the cards' axis
  double radius = 0;             // largest distance of a vertex from the centre
  double horizontal_radius = 0;  // largest distance of a vertex from the vertical axis through the centre
};

// Bounds, sphere and axis radius over every instance of every primitive's vertices. Throws
// std::invalid_argument for a scene without vertices.
SourceGeometry measure(const render::Scene& scene);

struct Layout {
  int atlas_width = 0, atlas_height = 0;
  int padding_px = 0;
  double frame_half_extent = 0;         // octahedral W; billboards: the vertical cards' half extent
  std::vector<render::BakeView> views;  // octahedral: frame (i, j) is views[j N + i]
  std::vector<Card> cards;              // impostor.glb's cards (cutouts not yet fitted: full frames)
  std::vector<int> card_view;           // the view each card shows
};

// Throws std::invalid_argument naming the parameter when the parameters cannot give an atlas
// (padding too wide for the frame, an atlas beyond 16384 px, too few frames).
Layout plan_layout(const LayoutParams& params, const SourceGeometry& geometry);

// The texel (m) the atlas would have for this geometry and these parameters: 2 W / frame_px.
// Throws as plan_layout().
double atlas_texel(const LayoutParams& params, const SourceGeometry& geometry);

}  // namespace sylva::impostor
