// The adapter of stage `hierarchy`: declares the parameters, reads the one input tree, runs the
// core (reconstruct.h) and writes tree.sylt and hierarchy.json; the textures the tree's materials
// name are passed on as links. Every problem becomes a StageError naming the file it read.
#include "stages/hierarchy/hierarchy_stage.h"

#include "libs/tree/sylt_format.h"
#include "stages/hierarchy/hierarchy_error.h"
#include "stages/hierarchy/reconstruct.h"
#include "stages/hierarchy/report.h"

namespace sylva {

namespace {

using hierarchy::ClassifyMode;

ClassifyMode classify_mode(const std::string& s) {
  if (s == "names") return ClassifyMode::kNames;
  if (s == "material") return ClassifyMode::kMaterial;
  if (s == "geometry") return ClassifyMode::kGeometry;
  return ClassifyMode::kAuto;
}

class HierarchyStage final : public Stage {
 public:
  HierarchyStage() {
    info_.name = "hierarchy";
    info_.version = 1;
    info_.summary =
        "reconstruct an imported mesh's parts, hierarchy and skeleton (Celba Alg. 1 and 2, slice-and-fit "
        "centre lines)";
    info_.params = {
        Param::real("weld_tolerance", 1e-5)
            .range(0, 1)
            .describe("m: vertices closer than this are one vertex before parts are split (Alg. 1); 0 = "
                      "shared indices only"),
        Param::choice("classify", {"auto", "names", "material", "geometry"}, "auto")
            .describe("branch or leaf: Celba's names br<level>*/lf*, the material (alpha mask/blend), the "
                      "geometry (small and flat), or auto = names, then material, then geometry"),
        Param::real("leaf_max_size", 1.0)
            .range(1e-4, 100)
            .describe("m: the longest extent of a part the geometry rule may call a leaf"),
        Param::real("leaf_flatness", 0.1)
            .range(0, 1)
            .describe("a part is flat when its thinnest extent is below this fraction of its middle one"),
        Param::choice("leaf_point", {"petiole", "centroid"}, "petiole")
            .describe("a leaf's significant point: petiole (Celba -m1, lowest texture v) or centroid (-m2)"),
        Param::real("tolerance", 0.05)
            .range(0, 100)
            .describe("m: bounding boxes grow by this for connection tests (Alg. 2, Celba's -f)"),
        Param::real("slice_radii", 1.0).range(0.1, 100).describe("skeleton slice length in base radii"),
        Param::integer("max_slices", 256).range(2, 4096).describe("most skeleton nodes per branch"),
        Param::integer("fit_iterations", 2)
            .range(0, 10)
            .describe("re-slicing rounds along the fitted centre line"),
    };
    info_.inputs = InputSpec{{"tree"}, 1, 1, "one imported tree: tree.sylt with source geometry"};
    info_.output_type = "tree";
    info_.outputs = {"tree.sylt", "hierarchy.json", "*.png", "*.jpg", "*.jpeg"};
  }

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    // 1. Read.
    const InputArtifact& in = ctx.inputs().front();
    const ArtifactFile* sylt = in.file("tree.sylt");
    if (!sylt) throw StageError("input '" + in.node + "' has no tree.sylt");
    const std::string where = sylt->path.string();
    tree::Tree tree;
    try {
      tree = tree::decode_sylt(ctx.read_input(*sylt), where);
    } catch (const tree::TreeFormatError& e) {
      throw StageError(e.what());
    }

    // 2. Reconstruct (pure core).
    hierarchy::ReconstructOptions o;
    o.weld_tolerance = ctx.real("weld_tolerance");
    o.classify.mode = classify_mode(ctx.string("classify"));
    o.classify.leaf_max_size = ctx.real("leaf_max_size");
    o.classify.leaf_flatness = ctx.real("leaf_flatness");
    o.leaf_point = ctx.string("leaf_point") == "centroid" ? hierarchy::LeafPoint::kCentroid
                                                          : hierarchy::LeafPoint::kPetiole;
    o.tolerance = ctx.real("tolerance");
    o.fit.slice_radii = ctx.real("slice_radii");
    o.fit.max_slices = static_cast<int>(ctx.integer("max_slices"));
    o.fit.iterations = static_cast<int>(ctx.integer("fit_iterations"));
    hierarchy::Reconstruction r;
    try {
      r = hierarchy::reconstruct(tree, o);
    } catch (const hierarchy::HierarchyError& e) {
      throw StageError(where + ": " + e.what());
    }
    ctx.check_cancelled();

    // 3. Write: the tree, the textures it names (linked), the report.
    std::string bytes;
    try {
      bytes = tree::encode_sylt(r.tree);
    } catch (const tree::TreeFormatError& e) {
      throw StageError(where + ": the reconstructed tree cannot be written: " + e.what());
    }
    ctx.write_output("tree.sylt", bytes);
    const tree::Materials& m = r.tree.materials;
    for (const std::string& name : {m.bark_texture, m.leaf_texture}) {
      if (name.empty() || (&name != &m.bark_texture && name == m.bark_texture)) continue;
      const ArtifactFile* f = in.file(name);
      if (!f)
        throw StageError(where + ": the tree's texture '" + name + "' is not a file of input '" + in.node +
                         "'");
      ctx.link_output(name, *f);
    }
    ctx.write_output("hierarchy.json", hierarchy::report_json(r.report, r.tree.source).dump(2) + "\n");
  }

 private:
  StageInfo info_;
};

}  // namespace

std::unique_ptr<Stage> make_hierarchy_stage() { return std::make_unique<HierarchyStage>(); }

}  // namespace sylva
