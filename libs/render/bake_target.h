// Private: the targets an impostor bake draws an atlas row into, and their read-back into the
// maps (impostor_renderer.cpp). Every function expects the context current.
//
// Two layouts:
//  - kLayered (msaa 1, the stage's default): opaque and masked primitives write one packed
//    RGBA16UI texel (colour, normal, depth rounded to 8 bits and a covered flag), blended ones
//    blend into three RGBA16 layers of their own; read-back composites the lines over the opaque
//    texel (bake_layers.h). llvmpipe's CPU per shaded 4 x 4 block grows with every attachment
//    and its bytes, and 93 % of an adult tree's primitives are opaque or masked: a seventh less
//    rasteriser CPU on an adult tree.
//  - kBlended (any msaa): three colour attachments in one pass (colour RGBA8, normal RGBA16,
//    depth RGBA16; 16-bit so that dividing the resolved, coverage-weighted values by the
//    coverage keeps 8 bits of precision). Every fragment writes its alpha as the alpha of all
//    three outputs, so after the MSAA resolve each attachment holds value * coverage (the
//    background is 0): dividing by the attachment's alpha gives the covered samples' average.
#pragma once

#include <cstdint>
#include <vector>

#include "libs/render/gl_util.h"
#include "libs/render/impostor_renderer.h"

namespace sylva::render::detail {

enum class BakeLayout { kBlended, kLayered };

struct BakeTarget {
  int width = 0, height = 0;
  GLuint draw_fbo = 0, resolve_fbo = 0;  // resolve_fbo == draw_fbo without multisampling
  BakeLayout layout = BakeLayout::kBlended;
};

// A row's attachments as read back (RGBA each), kept from row to row: allocating them per row
// cost more CPU in page faults than reading them (docs/performance.md). kBlended: color (8-bit),
// normal, depth; kLayered: packed, and the blended layers in color16, normal, depth.
struct RowPixels {
  std::vector<std::uint8_t> color;
  std::vector<std::uint16_t> normal, depth, packed, color16;
};

// A w x h target of `layout` (kBlended: msaa samples per texel). Throws RenderError when the
// device cannot make it.
BakeTarget make_bake_target(GlObjects& gl, int w, int h, int msaa, BakeLayout layout);

// kBlended: resolves the row, reads the three attachments back into `px` (grown as needed) and
// writes the divided values into the maps at rows [band_y, band_y + height).
void read_bake_row(const BakeTarget& t, int band_y, RowPixels& px, BakedMaps& out);

// kLayered: reads the packed layer back (and the blended layers when the scene has blended
// primitives; `px` is only ever used for one scene) into `px`, and writes the composited texels
// into the maps at rows [band_y, band_y + height) (bake_layers.h).
void read_layered_row(const BakeTarget& t, int band_y, bool blended, RowPixels& px, BakedMaps& out);

}  // namespace sylva::render::detail
