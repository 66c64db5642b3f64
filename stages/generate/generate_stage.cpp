// The thin adapter of stage `generate`: declares the parameters, reads the preset file, runs
// the pure generator (weber_penn.h) and the texture synthesis (textures.h), writes the outputs.
// Seed: Nystad 2010, Appendix A (the preset's parameters) and §5.2.2 (one seeded PRNG).
#include "stages/generate/generate_stage.h"

#include <nlohmann/json.hpp>

#include "libs/image/png.h"
#include "libs/tree/stats.h"
#include "libs/tree/sylt_format.h"
#include "stages/generate/card_atlas.h"
#include "stages/generate/mip_safe_alpha.h"
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
    info_.version = 7;  // 2: cards, LAI-fitted foliage, ground clearance, .sylt version 2, stats.json;
                        // 3: needle brushes drawn as projections (tuft, spray); 4: mip-safe halo
                        // chosen on drawn (trilinear) coverage down to one texel per cell;
                        // 6: per-level Clumps/ClumpSize (issue 9: the oak's limb clumps);
                        // 7: Hem/HemV (issue 9: the weeping willow's lifted curtains), TrunkUp
                        // (the columnar poplar's upright leader), ShapeFloor (the spruce's point),
                        // Pendulous (the willow's shoots that stood up)
    info_.summary = "parametric tree from a species preset (Weber-Penn with da Vinci/Murray rules)";
    info_.output_type = "tree";
    info_.outputs = {"tree.sylt", "stats.json", "bark.png", "leaves.png"};
    info_.inputs = {{}, 0, 0, "none: the species preset is a file parameter"};
    info_.params = {
        Param::path("preset").describe("species preset YAML (configs/species/<name>.yaml)"),
        Param::choice("age", {"young", "middle", "adult"}, "adult").describe("age variant of the preset"),
        Param::integer("seed", 1).range(0, 9007199254740991.0).describe("seed of every random choice"),
        Param::integer("levels", 0)
            .range(0, 8)
            .describe("branch levels incl. the trunk; 0 = the preset's Levels"),
        Param::real("max_node_spacing_m", 0.5)
            .range(0, 100)
            .describe("longest segment between skeleton nodes (m); 0 = no extra nodes (Nystad 4.3.2)"),
        Param::real("leaf_density", 1.0)
            .range(0, 4)
            .describe("multiplies the preset's Leaves (leaf or needle count) and its leaf-area-index target"),
        Param::integer("texture_size", 512)
            .range(16, 4096)
            .require_power_of_two()
            .describe("bark and leaf atlas size in pixels (power of two)"),
        Param::choice("foliage", {"cards", "leaves", "needles"}, "cards")
            .describe("cards: twig cards (broadleaves) or shoot cards (conifers), the games default; "
                      "leaves / needles: one quad per leaf or one needle each (hero close-ups)"),
    };
  }

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    // 1. Parse the preset.
    const std::filesystem::path preset_path = ctx.param_file("preset");
    generate::SpeciesPreset species;
    try {
      species = generate::parse_species_preset(ctx.read_param_file("preset"), preset_path.string());
    } catch (const generate::PresetParseError& e) {
      throw StageError(e.what());
    }
    const generate::AgeVariant& variant = species.age(ctx.string("age"));
    const auto texture_size = static_cast<int>(ctx.integer("texture_size"));
    if ((texture_size & (texture_size - 1)) != 0)
      throw StageError("texture_size " + std::to_string(texture_size) + " is not a power of two");
    // 2. Generate the tree (pure core).
    const std::string foliage = ctx.string("foliage");
    const bool conifer = variant.params.foliage == generate::Foliage::kNeedles;
    if (foliage == "leaves" && conifer)
      throw StageError(preset_path.string() + ": foliage 'leaves' needs a broadleaf preset; " +
                       species.species + " has needles (use 'needles' or 'cards')");
    if (foliage == "needles" && !conifer)
      throw StageError(preset_path.string() + ": foliage 'needles' needs a conifer preset; " +
                       species.species + " has leaves (use 'leaves' or 'cards')");
    const bool cards = foliage == "cards";
    // The atlas first: its cells' leaf coverage sets how much leaf area each quad carries.
    Rng leaf_rng = ctx.rng("leaves");
    generate::Rgba8 leaves;
    generate::GenerateOptions options;
    if (cards) {
      generate::CardAtlas atlas =
          generate::make_card_atlas(species.card, species.leaf, species.bark, texture_size, leaf_rng);
      leaves = std::move(atlas.image);
      options.atlas = {atlas.columns, atlas.rows, atlas.coverage};
      options.foliage = generate::FoliageMode::kCards;
    } else {
      std::vector<float> coverage;
      leaves = generate::make_leaf_atlas(species.leaf, texture_size, leaf_rng, conifer ? nullptr : &coverage);
      options.atlas = {2, 2, coverage};
      options.foliage = generate::FoliageMode::kSingle;
    }
    // Mip-safe alpha: the atlas keeps its coverage under the plain mipmaps every client builds.
    const generate::MipSafety mips =
        generate::make_mip_safe(leaves, options.atlas.columns, options.atlas.rows);
    options.levels = static_cast<int>(ctx.integer("levels"));
    options.max_node_spacing = ctx.real("max_node_spacing_m");
    options.leaf_density = ctx.real("leaf_density");
    options.name = species.species + "/" + variant.age + " seed " + std::to_string(ctx.integer("seed"));
    Rng rng = ctx.rng("tree");
    tree::Tree tree;
    generate::FoliageResult fit;
    options.foliage_result = &fit;
    try {
      tree = generate::generate_tree(variant.params, options, rng);
    } catch (const std::length_error& e) {
      throw StageError(preset_path.string() + ": " + e.what());
    } catch (const std::invalid_argument& e) {
      throw StageError(preset_path.string() + ": " + e.what());
    }
    ctx.check_cancelled();
    // 3. The bark texture, from its own stream so it does not depend on the tree's parameters.
    Rng bark_rng = ctx.rng("bark");
    const generate::Rgba8 bark = generate::make_bark_texture(species.bark, texture_size, bark_rng);
    // 4. Write: the tree, the textures, and the statistics (docs/stages/generate.md).
    ctx.write_output("tree.sylt", tree::encode_sylt(tree));
    const tree::TreeStats st = tree::compute_stats(tree);
    nlohmann::json stats = nlohmann::json::parse(tree::format_stats_json(st));
    stats["foliage"] = {
        {"mode", foliage},
        {"kind", cards ? (conifer ? "shoot_cards" : "twig_cards") : (conifer ? "needles" : "leaves")},
        {"target_lai", variant.params.leaf_area_index * options.leaf_density},
        {"published_lai_range", {species.lai_min, species.lai_max}},
        {"lai_source", species.lai_source},
        {"card_scale", fit.card_scale},
        {"card_layers", fit.layers},
        {"elements", fit.elements},
        {"atlas_halo_gain", mips.gain},
        {"atlas_halo_cap", mips.cap},
        {"atlas_mip_lods", mips.lods},
        {"atlas_mip_coverage", mips.coverage},
        {"atlas_mip_coverage_without_halo", mips.coverage_plain}};
    ctx.write_output("stats.json", stats.dump(2) + "\n");
    try {
      const auto png = [](const generate::Rgba8& pixels) {
        const std::vector<std::uint8_t> bytes = image::encode_png(to_image(pixels));
        return std::string(bytes.begin(), bytes.end());
      };
      ctx.write_output("bark.png", png(bark));
      ctx.write_output("leaves.png", png(leaves));
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
