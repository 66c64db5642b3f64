// impostor.glb: the cards of an impostor as plain glTF any viewer shows (three.js, Blender,
// Babylon.js): for billboards the ring of vertical cards and the top card; for the octahedral
// kinds a cross of the four horizon frames nearest azimuths 0, 90, 180 and 270°, as a fallback
// for viewers without the impostor shader. Each card is its cutout
// polygon (cutout.h), a vertical card cut in two at the vertical axis through its centre (each
// half its own primitive, so viewers that sort blended primitives far to near draw the ring of
// half-planes in the right order), single-sided (seen from its frame's direction only, so opposite cards
// sharing a plane never fight), in one unlit material (KHR_materials_unlit: the embedded image
// is lit already, bake.h) over one embedded image: alphaMode BLEND by
// default, because the image's alpha is coverage and a viewer's mipmaps average it, so the cards
// keep their coverage at every distance (alpha-testing the same mips at a cutoff thins sparse
// crowns away as they shrink); MASK on request.
#pragma once

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "libs/impostor/impostor_json.h"

namespace sylva::impostor {

struct GlbCard {
  Card card;                       // geometry and cutout (Card::x..h are the atlas rectangle)
  std::array<double, 3> normal{};  // the vertex normal the card is lit with (unit)
  int image_x = 0, image_y = 0;    // where the card's frame sits in the embedded image
};

struct GlbImage {
  std::string png;  // encoded PNG bytes
  int width = 0, height = 0;
};

// The GLB bytes; `extras` goes into the node's extras. Throws gltf::GltfError.
struct GlbAlpha {
  bool blend = true;  // alphaMode BLEND; false: MASK at `cutoff`
  float cutoff = 0.5f;
};
std::string encode_impostor_glb(const std::vector<GlbCard>& cards, const GlbImage& image,
                                const GlbAlpha& alpha, const nlohmann::json& extras);

// The polygons (card uv, counter-clockwise) a card is written as: each of a vertical card's
// cutout polygons (the cutout, then the lower cutout when there is one) cut at u = 1/2 (the
// vertical through its centre) into its non-degenerate halves; the top card whole.
std::vector<std::vector<std::array<double, 2>>> card_pieces(const Card& c);

// Triangles encode_impostor_glb writes for these cards (a fan per piece).
std::size_t card_triangles(const std::vector<GlbCard>& cards);

}  // namespace sylva::impostor
