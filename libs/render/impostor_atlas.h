// The maps of a (hemi-)octahedral impostor as the scene renderer draws them (Scene::impostors,
// scene.h): impostor.json's straight-alpha PNGs premultiplied by coverage, the contract of the
// reference shader (shaders/octahedral_impostor.frag: "Both maps are uploaded premultiplied by
// coverage"), so that texture filtering and mip levels weight every texel by what it covers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "libs/image/image.h"
#include "libs/impostor/impostor_json.h"
#include "libs/render/scene.h"

namespace sylva::render {

// The geometry impostor.json records (frames, sphere, frame half extent, padding, mip levels).
ImpostorGeometry impostor_geometry(const impostor::ImpostorInfo& info);

// Premultiplies an impostor's maps in place, the reference shader's contract: colour rgb =
// sRGB(linear(rgb) * a), normal rgb = round(rgb * a / 255), alpha and depth unchanged. Both are
// RGBA8 rows of the same size (color's alpha = coverage). Used by the scene renderer's atlases and
// by ImpostorRenderer::render_octahedral (octahedral_render.cpp).
void premultiply_impostor_maps(std::vector<std::uint8_t>& color, std::vector<std::uint8_t>& normal_depth);

// The reference shader's optional SYLVA_EMPTY_DISTANCE cull map of `atlas`: per cell of
// cell_px x cell_px texels ((atlas_px / cell_px)^2 cells, top row first; cell_px must divide
// frame_px), a lower bound, in texels (at most 255), of the Chebyshev distance from any point of
// the cell to any texel of the same frame with a non-zero byte in either map: 0 for a cell that
// holds such a texel or touches one that does, else cell_px times the number of cells between
// (chessboard); 255 in an empty frame and where that exceeds 255.
std::vector<std::uint8_t> impostor_empty_distance(const ImpostorAtlas& atlas, int cell_px);

// color: sRGB RGB with straight alpha = coverage; normal_depth: rgb = normal * 0.5 + 0.5, a =
// depth (docs/stages/impostor.md "Maps"). Premultiplied: colour rgb = sRGB(linear(rgb) * a),
// normal rgb = round(rgb * a / 255), alpha and depth unchanged. Throws RenderError (one line,
// naming `name`) when the maps are not both frames_per_side * frame_px square. The maps' pixels
// move into the atlas (pass temporaries: a 4096-px atlas is 64 MB a map).
ImpostorAtlas make_impostor_atlas(std::string name, image::Image color, image::Image normal_depth,
                                  const ImpostorGeometry& geometry);

}  // namespace sylva::render
