// The report is the answer to "was anything lost?": every part left out is listed with its
// triangles and size, and every branch with how well its circles fit.
#include "stages/hierarchy/report.h"

namespace sylva::hierarchy {

nlohmann::json report_json(const Report& r, const tree::SourceGeometry& g) {
  nlohmann::json left = nlohmann::json::array();
  std::size_t left_triangles = 0;
  for (const LeftOutPart& p : r.left_out) {
    left.push_back({{"part", p.part},
                    {"primitive", g.primitives[p.primitive].name},
                    {"kind", p.kind},
                    {"triangles", p.triangles},
                    {"size_m", p.size_m}});
    left_triangles += p.triangles;
  }
  nlohmann::json branches = nlohmann::json::array();
  for (const BranchReport& b : r.branches)
    branches.push_back({{"part", b.part},
                        {"parent", b.parent},
                        {"level", b.level},
                        {"nodes", b.nodes},
                        {"base_radius_m", b.base_radius_m},
                        {"fit_rms_m", b.fit_rms_m},
                        {"axis_fallback", b.axis_fallback}});
  return {
      {"parts", r.parts},
      {"branch_parts", r.branch_parts},
      {"leaf_parts", r.leaf_parts},
      {"skipped_parts", r.skipped_parts},
      {"classify_fallback", r.classify_fallback ? "geometry" : "none"},
      {"levels", r.levels_from_names ? "names" : "derived"},
      {"branches_by_level", r.branches_by_level},
      {"leaves", r.leaves},
      {"leaves_below_top_level", r.leaves_below_top},
      {"leaves_without_uvs", r.leaves_without_uvs},
      {"unconnected", {{"count", r.left_out.size()}, {"triangles", left_triangles}, {"parts", left}}},
      {"branches", branches},
  };
}

}  // namespace sylva::hierarchy
