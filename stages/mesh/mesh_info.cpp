#include "stages/mesh/mesh_info.h"

namespace sylva {

namespace {
// 2: junction collapse, insets, windowed ring frames, ring merging. 3: libs/gltf writes no
// tangents without a normal map; colours from libs/tree/default_colors.h. 4: cards (atlas cells,
// card-drawn twigs), no tangents computed, bark tint, LAI statistics. 5: creased foot, radii
// pre-compensated for Catmull-Clark, joint swelling correction (docs/stages/mesh.md). 6: ring thinning
// (ring_tolerance), thin branches not subdivided (smooth_radius): the hero budget.
constexpr int kVersion = 6;
}  // namespace

StageInfo mesh_stage_info() {
  StageInfo info;
  info.name = "mesh";
  info.version = kVersion;
  info.summary =
      "tree -> GLB: one connected quad mesh with box joints (Nystad), Catmull-Clark, leaf cards, needles";
  info.inputs =
      InputSpec{{"tree"}, 1, 1, "one tree (generate or import): tree.sylt and the textures it names"};
  info.output_type = "mesh";
  info.outputs = {"tree.glb", "tree.gltf"};
  info.params = {
      Param::integer("max_level", -1)
          .range(-1, 16)
          .describe("highest branch level meshed (trunk 0); -1 = every level"),
      Param::integer("subdivision", 1)
          .range(0, 3)
          .describe("Catmull-Clark levels (each multiplies the quads by 4)"),
      Param::boolean("open_base", false).describe("leave the trunk base open (default: closed)"),
      Param::boolean("foliage", true)
          .describe("leaf quads or cards (alpha-masked, double-sided) and needles"),
      Param::boolean("mesh_card_twigs", false)
          .describe("also mesh the twigs that twig/shoot cards draw (default: the cards draw them)"),
      Param::real("min_radius_m", 0.001)
          .range(1e-5, 1)
          .describe("thinner skeleton nodes (tapered tips reach 0) are meshed at this radius (m)"),
      Param::real("ring_tolerance", 0.0005)
          .range(0, 0.05)
          .describe("rings without children are left out where the branch stays within this fraction of "
                    "the tree's size of its axis and radius; 0 = keep every ring"),
      Param::real("smooth_radius", 0.0015)
          .range(0, 1)
          .describe("at subdivision 1, branches thinner at their base than this fraction of the tree's size "
                    "are not subdivided; 0 = subdivide every branch"),
      Param::integer("bark_repeat", 1).range(1, 16).describe("bark texture repeats around a branch"),
      Param::choice("subdivider", {"native", "openmesh"}, "native")
          .describe("Catmull-Clark implementation: native (fast) or OpenMesh's CatmullClarkT (reference)"),
      Param::choice("format", {"glb", "gltf"}, "glb")
          .describe("glb, or a self-contained .gltf (base64 buffer)"),
      Param::boolean("draco", false).describe("KHR_draco_mesh_compression for the triangle primitives"),
      Param::integer("draco_position_bits", 14).range(8, 30).describe("Draco quantisation of positions"),
      Param::integer("draco_normal_bits", 10).range(4, 30).describe("Draco quantisation of normals"),
      Param::integer("draco_texcoord_bits", 12).range(4, 30).describe("Draco quantisation of uvs"),
      Param::integer("draco_generic_bits", 12)
          .range(4, 30)
          .describe("Draco quantisation of generic attributes (none written today)"),
      Param::integer("draco_level", 7)
          .range(0, 10)
          .describe("Draco compression level (0 fastest, 10 smallest)"),
      Param::boolean("self_intersections", false)
          .describe("count self-intersecting triangle pairs of the bark (CGAL) into the statistics; slow"),
      Param::boolean("keep_source", false)
          .describe("an imported tree: write the imported model itself instead of re-meshing its "
                    "reconstructed skeleton (an error for a tree that is not an imported mesh)"),
  };
  return info;
}

}  // namespace sylva
