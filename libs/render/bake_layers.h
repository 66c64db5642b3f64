// The impostor bake's two layers composited into the maps' texels (impostor_renderer.h,
// "Bake"; docs/stages/impostor.md, "Maps").
//
// Without multisampling a texel is either covered by an opaque or masked primitive or not, so
// the baker draws those primitives into one packed layer that holds what the maps store, each
// value already rounded to 8 bits (one 16-bit RGBA attachment instead of three: llvmpipe's cost
// per shaded 4 x 4 block grows with every attachment, docs/performance.md):
//
//   packed[0] = r | g << 8      r, g, b: sRGB-encoded base colour
//   packed[1] = b | nx << 8     nx, ny, nz: normal * 0.5 + 0.5
//   packed[2] = ny | nz << 8
//   packed[3] = depth | 0xFF00  depth: the map's depth; 0xFF00: covered (0 = not covered)
//
// Blended primitives (a LOD level's lines) are drawn after them into three 16-bit RGBA layers
// cleared to 0, over each other (colour and alpha "over", the colour in sRGB encoding as the
// scene renderer blends it): rgb = the lines' premultiplied composite of sRGB colour, normal *
// 0.5 + 0.5 and depth (in r of the third), alpha = the lines' coverage a. The texel is then the
// lines over the opaque texel, as drawing them over it would have composited it: value = (line
// rgb + (1 - a) o v) / (a + (1 - a) o), coverage a + (1 - a) o, o = 1 where the opaque layer
// covers the texel and v its value; the mean normal keeps its length (at most 1), as the maps
// store it.
#pragma once

#include <cstdint>

namespace sylva::render {

// One texel: `packed` the opaque layer's 4 values, `line_*` the blended layers' 4 values each
// (RGBA, 0..65535). Writes colour (sRGB, straight alpha = coverage) and normal_depth (RGB =
// normal * 0.5 + 0.5, A = depth) as 4 bytes each; leaves both untouched where nothing covers
// the texel.
void composite_bake_texel(const std::uint16_t* packed, const std::uint16_t* line_color,
                          const std::uint16_t* line_normal, const std::uint16_t* line_depth,
                          std::uint8_t* color, std::uint8_t* normal_depth);

}  // namespace sylva::render
