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
// by impostor_renderer.cpp.
void premultiply_impostor_maps(std::vector<std::uint8_t>& color, std::vector<std::uint8_t>& normal_depth);

// color: sRGB RGB with straight alpha = coverage; normal_depth: rgb = normal * 0.5 + 0.5, a =
// depth (docs/stages/impostor.md "Maps"). Premultiplied: colour rgb = sRGB(linear(rgb) * a),
// normal rgb = round(rgb * a / 255), alpha and depth unchanged. Throws RenderError (one line,
// naming `name`) when the maps are not both frames_per_side * frame_px square. The maps' pixels
// move into the atlas (pass temporaries: a 4096-px atlas is 64 MB a map).
ImpostorAtlas make_impostor_atlas(std::string name, image::Image color, image::Image normal_depth,
                                  const ImpostorGeometry& geometry);

}  // namespace sylva::render
