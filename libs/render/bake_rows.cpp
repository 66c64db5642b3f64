// The atlas layout of an impostor bake (bake_rows.h).
#include "libs/render/bake_rows.h"

#include <map>
#include <string>
#include <utility>

#include "libs/render/bake_programs.h"

namespace sylva::render::detail {

void validate_bake(std::span<const BakeView> views, const BakeOptions& o, const DeviceLimits& limits) {
  check_target_size("atlas", o.atlas_width, o.atlas_height, o.msaa, limits);
  if (!(o.line_width_px >= 1) || !(o.line_alpha_scale > 0 && o.line_alpha_scale <= 1))
    throw RenderError("line width must be at least 1 texel and the line alpha scale in (0, 1]");
  for (std::size_t v = 0; v < views.size(); ++v) {
    const BakeView& b = views[v];
    if (b.x < 0 || b.y < 0 || b.w < 1 || b.h < 1 || b.x + b.w > o.atlas_width || b.y + b.h > o.atlas_height)
      throw RenderError("bake view " + std::to_string(v) + " lies outside the atlas");
    if (!(b.half_width > 0) || !(b.half_height > 0) || !(b.depth_radius > 0))
      throw RenderError("bake view " + std::to_string(v) + " has a non-positive extent");
  }
}

std::vector<BakeRow> plan_rows(std::span<const BakeView> views, const BakeOptions& o) {
  std::map<std::pair<int, int>, std::vector<std::size_t>> by_row;  // (y, h) -> views, in view order
  for (std::size_t v = 0; v < views.size(); ++v) by_row[{views[v].y, views[v].h}].push_back(v);
  std::vector<BakeRow> rows;
  for (const auto& [key, idx] : by_row) {
    if (idx.size() > kMaxRowViews)
      throw RenderError("an atlas row holds " + std::to_string(idx.size()) + " views; at most " +
                        std::to_string(kMaxRowViews) + " are supported");
    BakeRow row;
    row.y = key.first;
    row.h = key.second;
    row.views = idx;
    for (std::size_t v : idx) {
      const BakeView& bv = views[v];
      const Vec3 r = bv.right / bv.half_width, u = bv.up / bv.half_height, d = bv.dir / bv.depth_radius;
      const float cx = (bv.x + 0.5f * bv.w) / float(o.atlas_width) * 2 - 1;
      const float hw = float(bv.w) / float(o.atlas_width);
      const float hh = float(bv.h) / float(row.h);  // the row fills its band's height
      const float vals[20] = {
          bv.center.x(), bv.center.y(), bv.center.z(), 0, r.x(), r.y(), r.z(), 0, u.x(), u.y(), u.z(), 0,
          d.x(),         d.y(),         d.z(),         0, cx,    0.f,   hw,    hh};
      row.uniforms.insert(row.uniforms.end(), vals, vals + 20);
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace sylva::render::detail
