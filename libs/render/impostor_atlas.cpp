// Premultiplying an impostor's maps for the reference shader (impostor_atlas.h).
#include "libs/render/impostor_atlas.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "libs/render/renderer.h"

namespace sylva::render {

// One table row per alpha that occurs: sRGB(linear(c) * a / 255) for every c, instead of two
// pow() per channel.
void premultiply_impostor_maps(std::vector<std::uint8_t>& color, std::vector<std::uint8_t>& normal_depth) {
  std::array<double, 256> lin{};
  for (int i = 0; i < 256; ++i) {
    const double c = i / 255.0;
    lin[std::size_t(i)] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  }
  auto srgb8 = [](double c) {
    c = std::clamp(c, 0.0, 1.0);
    return std::uint8_t(
        std::lround(255 * (c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055)));
  };
  std::vector<std::array<std::uint8_t, 256>> table;  // [a][c], built for the alphas that occur
  std::array<int, 256> row_of{};
  row_of.fill(-1);
  for (std::size_t i = 0; i < color.size(); i += 4) {
    const int al = color[i + 3];
    if (al == 255) continue;
    if (row_of[std::size_t(al)] < 0) {
      row_of[std::size_t(al)] = int(table.size());
      std::array<std::uint8_t, 256> t{};
      for (int c = 0; c < 256; ++c) t[std::size_t(c)] = al == 0 ? 0 : srgb8(lin[std::size_t(c)] * al / 255.0);
      table.push_back(t);
    }
    const auto& t = table[std::size_t(row_of[std::size_t(al)])];
    for (std::size_t c = 0; c < 3; ++c) {
      color[i + c] = t[color[i + c]];
      normal_depth[i + c] = std::uint8_t((normal_depth[i + c] * al + 127) / 255);
    }
  }
}

ImpostorGeometry impostor_geometry(const impostor::ImpostorInfo& info) {
  ImpostorGeometry g;
  g.frames_per_side = info.frames_per_side;
  g.hemi = info.hemi;
  g.center = Vec3(float(info.sphere_center[0]), float(info.sphere_center[1]), float(info.sphere_center[2]));
  g.radius = float(info.sphere_radius);
  g.half_extent = float(info.frame_half_extent);
  g.frame_px = info.frame_px;
  g.padding_px = info.padding_px;
  g.mip_levels = info.mip_levels;
  return g;
}

std::vector<std::uint8_t> impostor_empty_distance(const ImpostorAtlas& a, int cell_px) {
  const int fp = a.geometry.frame_px, cells = fp / cell_px, side = a.atlas_px / cell_px;
  // Cells holding a stored texel (each row of cells on its own: rows of the result apart).
  std::vector<std::uint8_t> held(std::size_t(side) * std::size_t(side), 0);
  tbb::parallel_for(0, side, [&](int cy) {
    for (int y = cy * cell_px; y < (cy + 1) * cell_px; ++y)
      for (int x = 0; x < a.atlas_px; ++x) {
        const std::size_t at = (std::size_t(y) * std::size_t(a.atlas_px) + std::size_t(x)) * 4;
        std::uint32_t c = 0, d = 0;
        std::memcpy(&c, &a.color[at], 4);
        std::memcpy(&d, &a.normal_depth[at], 4);
        if ((c | d) != 0) held[std::size_t(cy) * std::size_t(side) + std::size_t(x / cell_px)] = 1;
      }
  });
  // Per frame (each on its own), the chessboard distance in cells to the nearest held cell (two
  // chamfer passes with all eight neighbours at 1 are exact for it), then the gap between the
  // cells' boxes in texels.
  constexpr int kFar = 1 << 20;
  std::vector<std::uint8_t> out(held.size());
  const int frames = side / cells;
  tbb::parallel_for(0, frames * frames, [&](int f) {
    const int fx = (f % frames) * cells, fy = (f / frames) * cells;
    std::vector<int> dist(std::size_t(cells) * std::size_t(cells));
    auto at = [&](int x, int y) -> int& {
      return dist[std::size_t(y) * std::size_t(cells) + std::size_t(x)];
    };
    for (int y = 0; y < cells; ++y)
      for (int x = 0; x < cells; ++x)
        at(x, y) = held[std::size_t(fy + y) * std::size_t(side) + std::size_t(fx + x)] ? 0 : kFar;
    for (int y = 0; y < cells; ++y)
      for (int x = 0; x < cells; ++x) {
        int& d = at(x, y);
        if (x > 0) d = std::min(d, at(x - 1, y) + 1);
        if (y > 0) {
          d = std::min(d, at(x, y - 1) + 1);
          if (x > 0) d = std::min(d, at(x - 1, y - 1) + 1);
          if (x + 1 < cells) d = std::min(d, at(x + 1, y - 1) + 1);
        }
      }
    for (int y = cells - 1; y >= 0; --y)
      for (int x = cells - 1; x >= 0; --x) {
        int& d = at(x, y);
        if (x + 1 < cells) d = std::min(d, at(x + 1, y) + 1);
        if (y + 1 < cells) {
          d = std::min(d, at(x, y + 1) + 1);
          if (x + 1 < cells) d = std::min(d, at(x + 1, y + 1) + 1);
          if (x > 0) d = std::min(d, at(x - 1, y + 1) + 1);
        }
      }
    for (int y = 0; y < cells; ++y)
      for (int x = 0; x < cells; ++x) {
        const int d = at(x, y);
        out[std::size_t(fy + y) * std::size_t(side) + std::size_t(fx + x)] =
            std::uint8_t(d >= kFar ? 255 : std::min(255, std::max(0, d - 1) * cell_px));
      }
  });
  return out;
}

ImpostorAtlas make_impostor_atlas(std::string name, image::Image color, image::Image normal_depth,
                                  const ImpostorGeometry& g) {
  const int px = g.frames_per_side * g.frame_px;
  for (const image::Image* m : {&color, &normal_depth})
    if (m->width() != px || m->height() != px)
      throw RenderError("impostor '" + name + "': its maps must be " + std::to_string(px) + "x" +
                        std::to_string(px) + " pixels (frames_per_side x frame_px), got " +
                        std::to_string(m->width()) + "x" + std::to_string(m->height()));
  ImpostorAtlas a;
  a.name = std::move(name);
  a.atlas_px = px;
  a.geometry = g;
  a.color = std::move(color.bytes());
  a.normal_depth = std::move(normal_depth.bytes());
  premultiply_impostor_maps(a.color, a.normal_depth);
  return a;
}

}  // namespace sylva::render
