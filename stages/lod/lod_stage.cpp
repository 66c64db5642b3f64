// The thin adapter of stage `lod`: declares the parameters, reads the tree artifact, runs the
// pure chain (chain.h) and writes the chain's files (lod_gltf.h: lod.gltf with MSFT_lod,
// lod<i>.gltf + lod<i>.bin, leaves.png, ribbons variants), lod.json and full.glb (the
// full-detail model the levels are judged against).
// Seeds: Zhang et al. 2017 §3–§6 (parameters delta, epsilon, E1–E5, Γ, H, N); Remolar et al.
// FSA/VDF (leaves). docs/stages/lod.md lists every parameter with its equation.
#include "stages/lod/lod_stage.h"

#include <numbers>

#include "libs/gltf/writer.h"
#include "libs/image/png.h"
#include "libs/tree/sylt_format.h"
#include "stages/lod/chain.h"
#include "stages/lod/lod_gltf.h"
#include "stages/lod/lod_info.h"

namespace sylva {

namespace {

class LodStage : public Stage {
 public:
  LodStage() : info_(lod_stage_info()) {}

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    // 1. Read the tree.
    const InputArtifact& in = ctx.inputs()[0];
    const ArtifactFile* sylt = in.file("tree.sylt");
    if (!sylt) throw StageError("input '" + in.node + "' has no tree.sylt");
    tree::Tree tree;
    try {
      tree = tree::decode_sylt(ctx.read_input(*sylt), sylt->path.string());
    } catch (const std::exception& e) {
      throw StageError(sylt->path.string() + ": " + e.what());
    }
    lod::OutputTextures tex;
    if (!tree.materials.leaf_texture.empty()) {
      if (const ArtifactFile* f = in.file(tree.materials.leaf_texture)) tex.leaf_png = ctx.read_input(*f);
    }
    // 2. Options.
    lod::ChainOptions o = chain_options_from_params(ctx.params());
    o.check_cancelled = [&ctx] { ctx.check_cancelled(); };  // inside the long loops, not only after
    o.card_seed = ctx.rng("card_clusters").next_u64();      // the card clusters' survivors
    // The card clusters weigh each card by what its atlas cell draws (card_coverage.h), measured
    // on the atlas the levels are drawn with, at the leaves' MASK cutoff (lod_gltf.cpp: 0.5).
    if (o.card_cluster_px > 0 && !tex.leaf_png.empty()) {
      try {
        const image::Image atlas = image::decode_png(tex.leaf_png, tree.materials.leaf_texture);
        o.card_opacity =
            lod::measure_cell_opacity(atlas.bytes(), atlas.width(), atlas.height(), tree.materials);
      } catch (const std::exception& e) {
        throw StageError("input '" + in.node + "': leaf atlas " + tree.materials.leaf_texture + ": " +
                         e.what());
      }
    }
    // 3. The chain (pure core). An imported tree's level 0 and full detail are its own model
    // (docs/stages/lod.md "Imported trees"); the coarser levels come from its reconstruction.
    if (const std::string why = tree::missing_hierarchy(tree); !why.empty()) throw StageError(why);
    std::vector<lod::Level> levels;
    lod::Level full;
    try {
      const lod::Precomputed pre = lod::precompute(tree, o);
      levels = lod::build_chain(tree, pre, o);
      ctx.check_cancelled();
      full = lod::build_full_detail(tree, pre, o);
      if (!tree.source.empty()) {
        levels[0] = lod::source_level(tree, levels[0].spec);
        full = lod::source_level(tree, full.spec);
      }
    } catch (const std::invalid_argument& e) {
      throw StageError(e.what());
    }
    ctx.check_cancelled();
    // 4. Write: the linked chain, one file per level, shared buffers and atlas, the summary.
    const auto r = ctx.params().find("ribbons");
    const bool ribbons = r != ctx.params().end() && r->second.as_bool();
    try {
      for (const gltf::EncodedFile& f : lod::encode_chain_files(tree, levels, o.camera, tex, ribbons))
        ctx.write_output(f.name, f.bytes);
    } catch (const gltf::GltfError& e) {
      throw StageError(std::string("writing glTF: ") + e.what());
    }
    ctx.write_output(lodchain::kSummaryFile,
                     lodchain::write_lod_chain(lod::chain_summary(tree, levels, o, ribbons)));
    // The full-detail model the levels are judged against (the pack stage measures with it).
    try {
      ctx.write_output(lodchain::kFullDetailFile, lod::encode_full_detail(tree, std::move(full), tex));
    } catch (const gltf::GltfError& e) {
      throw StageError(std::string("writing ") + lodchain::kFullDetailFile + ": " + e.what());
    }
  }

 private:
  StageInfo info_;
};

}  // namespace

lod::ChainOptions chain_options_from_params(const Value::Object& params) {
  auto at = [&](const char* name) -> const Value& {
    auto it = params.find(name);
    if (it == params.end())
      throw std::invalid_argument(std::string("lod parameters: '") + name + "' is missing");
    return it->second;
  };
  lod::ChainOptions o;
  const Value::Object& cam = at("camera").as_object();
  o.camera = lodmodel::camera_from_degrees(cam.at("fov_y_deg").as_real(),
                                           static_cast<int>(cam.at("height_px").as_int()));
  o.pixel_error = at("pixel_error").as_real();
  o.levels = static_cast<int>(at("levels").as_int());
  for (const Value& v : at("errors_m").as_list()) o.errors.push_back(v.as_real());
  o.min_error = at("min_error_m").as_real();
  o.max_error = at("max_error_m").as_real();
  o.e1 = at("e1").as_real();
  o.e2 = at("e2").as_real();
  o.e3 = at("e3").as_real();
  o.e4 = at("e4").as_real();
  o.e5 = at("e5").as_real();
  o.torsion_limit = at("torsion_limit_deg").as_real() * std::numbers::pi / 180;
  o.max_edges = static_cast<int>(at("max_edges").as_int());
  o.topology = at("topology").as_bool();
  o.foliage = at("foliage").as_bool();
  o.card_cluster_px = at("card_cluster_px").as_real();
  o.card_size_px = at("card_size_px").as_real();
  o.card_coverage_check = at("card_coverage_check").as_real();
  o.card_max_scale = at("card_max_scale").as_real();
  o.card_places = at("card_places").as_bool();
  return o;
}

std::unique_ptr<Stage> make_lod_stage() { return std::make_unique<LodStage>(); }

}  // namespace sylva
