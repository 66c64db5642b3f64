// Coincident blended lines drawn as one, for the impostor baker (impostor_renderer.h).
//
// A LOD level draws each sub-pixel internode as three lines with the same endpoints, colours and
// alpha a, differing only in their normals (docs/stages/lod.md, "Line alpha"): at atlas resolution
// the three rasterise to the same texels and blend over each other. Drawn as one line that carries
// the k normals, with coverage 1 - (1 - a)^k and the normal mean weighted as "over" weights them
// (the copy drawn last a, the one before a(1 - a), ...), the line composites to exactly what the k
// overs give (colour: equal colours; alpha, normal, depth: the same weights), for a third of the
// rasterisation. The baker's fragment shader does the weighting (the normals are turned toward the
// view first, per copy, as it does for every line).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "libs/render/scene.h"

namespace sylva::render {

constexpr int kMaxMergedLines = 3;  // normals one merged line carries (three lines per internode)

struct MergedLines {
  // Two vertices per merged segment, drawn in order (no index buffer).
  std::vector<Vec3> positions;
  // normals[j]: copy j's normal at each vertex (copy 0 drawn first); a segment of fewer copies
  // repeats its last. Empty when the primitive has no normals.
  std::array<std::vector<Vec3>, kMaxMergedLines> normals;
  std::vector<Vec2> texcoords;  // empty when the primitive has none
  std::vector<Vec4> colors;     // empty when the primitive has none
  std::vector<float> copies;    // per vertex: how many lines the segment stands for, 1..kMaxMergedLines
  std::size_t source_segments = 0;
};

// The LINES primitive `p`'s segments in index order, each run of consecutive segments whose two
// endpoints (in the same order) have bit-identical positions, colours and texcoords merged into
// one segment of up to kMaxMergedLines copies (longer runs continue in a new segment). Only runs
// of consecutive segments merge: "over" does not commute for the normals, so a segment drawn in
// between keeps its place. Throws std::invalid_argument for a primitive that is not LINES or has
// an odd index count; indices must be in range (the caller checks them).
MergedLines merge_coincident_lines(const Primitive& p);

// The scene renderer draws LINES unlit (scene_programs.cpp), so a LOD level's three coincident
// lines per internode differ only in normals it does not use: k copies of colour c and alpha a
// "over" what is behind them as one line of alpha 1 - (1 - a)^k. For every LINES primitive of
// `scene` with a BLEND material, each run of coincident copies becomes that one line
// (Primitive::copies = k; no normals; indices 0, 1, 2, ...; the renderer raises the alpha per
// fragment). Exact in real arithmetic; the framebuffer rounds once instead of k times, so a pixel
// may differ by a level or two of 255 per line drawn over it. Forest views draw their levels so
// (forest_view.h): a third of the lines.
void merge_line_copies(Scene& scene);

}  // namespace sylva::render
