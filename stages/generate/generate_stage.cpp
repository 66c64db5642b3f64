// The thin adapter of stage `generate`: declares the parameters, reads the preset file, runs
// the pure generator (weber_penn.h) and the texture synthesis (textures.h), writes the outputs.
// Seed: Nystad 2010, Appendix A (the preset's parameters) and §5.2.2 (one seeded PRNG).
#include "stages/generate/generate_stage.h"

#include "libs/image/png.h"
#include "libs/tree/sylt_format.h"
#include "stages/generate/preset.h"
#include "stages/generate/textures.h"
#include "stages/generate/weber_penn.h"

namespace sylva {

namespace {

image::Image to_image(const generate::Rgba8& px) {
  image::Image img(px.width, px.height);
  img.bytes() = px.pixels;
  return img;
}

class GenerateStage : public Stage {
 public:
  GenerateStage() {
    info_.name = "generate";
    info_.version = 1;
    info_.summary = "parametric tree from a species preset (Weber-Penn with da Vinci/Murray rules)";
    info_.output_type = "tree";
    info_.inputs = {{}, 0, 0, "none: the species preset is a file parameter"};
    info_.params = {
        Param::path("preset").describe("species preset YAML (configs/species/<name>.yaml)"),
        Param::choice("age", {"young", "middle", "adult"}, "adult").describe("age variant of the preset"),
        Param::integer("seed", 1).range(0, 9007199254740991.0).describe("seed of every random choice"),
        Param::integer("levels", 0).range(0, 8).describe("branch levels incl. the trunk; 0 = the preset's Levels"),
        Param::real("max_node_spacing_m", 0.5)
            .range(0, 100)
            .describe("longest segment between skeleton nodes (m); 0 = no extra nodes (Nystad 4.3.2)"),
        Param::real("leaf_density", 1.0).range(0, 4).describe("multiplies the preset's Leaves (leaf or needle count)"),
        Param::integer("texture_size", 512).range(16, 4096).describe("bark and leaf atlas size in pixels (power of two)"),
    };
  }

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    // 1. Parse the preset.
    const std::filesystem::path preset_path = ctx.param_file("preset");
    generate::SpeciesPreset species;
    try {
      species = generate::load_species_preset(preset_path);
    } catch (const generate::PresetParseError& e) {
      throw StageError(e.what());
    }
    const generate::AgeVariant& variant = species.age(ctx.string("age"));
    const auto texture_size = static_cast<int>(ctx.integer("texture_size"));
    if ((texture_size & (texture_size - 1)) != 0)
      throw StageError("texture_size " + std::to_string(texture_size) + " is not a power of two");
    // 2. Generate the tree (pure core).
    generate::GenerateOptions options;
    options.levels = static_cast<int>(ctx.integer("levels"));
    options.max_node_spacing = ctx.real("max_node_spacing_m");
    options.leaf_density = ctx.real("leaf_density");
    options.name = species.species + "/" + variant.age + " seed " + std::to_string(ctx.integer("seed"));
    Rng rng = ctx.rng("tree");
    tree::Tree tree;
    try {
      tree = generate::generate_tree(variant.params, options, rng);
    } catch (const std::length_error& e) {
      throw StageError(preset_path.string() + ": " + e.what());
    } catch (const std::invalid_argument& e) {
      throw StageError(preset_path.string() + ": " + e.what());
    }
    ctx.check_cancelled();
    // 3. Textures, each from its own stream so they do not depend on the tree's parameters.
    Rng bark_rng = ctx.rng("bark");
    Rng leaf_rng = ctx.rng("leaves");
    const generate::Rgba8 bark = generate::make_bark_texture(species.bark, texture_size, bark_rng);
    generate::LeafLook leaf_look = species.leaf;
    const generate::Rgba8 leaves = generate::make_leaf_atlas(leaf_look, texture_size, leaf_rng);
    // 4. Write.
    tree::write_sylt(ctx.output_path("tree.sylt"), tree);
    try {
      image::write_png(to_image(bark), ctx.output_path("bark.png"));
      image::write_png(to_image(leaves), ctx.output_path("leaves.png"));
    } catch (const image::ImageError& e) {
      throw StageError(e.what());
    }
  }

 private:
  StageInfo info_;
};

}  // namespace

std::unique_ptr<Stage> make_generate_stage() { return std::make_unique<GenerateStage>(); }

}  // namespace sylva
