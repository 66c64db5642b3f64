// The preset reader: merging of ages over the shared parameters, and exact error messages with
// file:line:col for bad YAML.
#include "stages/generate/preset.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace sylva::generate {
namespace {

const char* kGood = R"(species: test_tree
name: Test tree
foliage: leaves
sources: ["hand-written for the test"]
textures:
  bark: { style: birch, color: [0.9, 0.9, 0.9], dark: [0.1, 0.1, 0.1] }
  leaf: { shape: spiny, color: [0.1, 0.3, 0.1], vein: [0.5, 0.6, 0.3] }
params:
  Shape: 1
  Scale: 10
  Leaves: 100
  levels:
    - { Length: 1, CurveRes: 4 }
    - { Branches: 10, Length: 0.5, BranchRatio: 0.4 }
  leaf: { Rotate: 90 }
ages:
  young:
    height_m: [1, 5]
    source: "a"
    params: { Scale: 3, levels: [ {}, { Branches: 5 } ] }
  middle:
    height_m: [4, 9]
    source: "b"
  adult:
    height_m: [8, 14]
    source: "c"
    params: { Levels: 2, levels: [ {}, {}, { Branches: 3 } ], LeafAreaIndex: 4.5, FoliageZone: 0.4 }
card: { style: spray, length_m: 0.3, aspect: 0.6, elements: 50, shoots: 3, layers: [2, 3], light_bias: 0.2 }
leaf_area_index: { range: [2, 5], source: "d" }
)";

std::string error_of(const std::string& text) {
  try {
    parse_species_preset(text, "t.yaml");
  } catch (const PresetParseError& e) {
    return e.what();
  }
  return "";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

// Ages override the shared parameters key by key; per-level entries merge by index.
TEST(Preset, AgesMergeOverSharedParams) {
  const SpeciesPreset s = parse_species_preset(kGood, "t.yaml");
  EXPECT_EQ(s.species, "test_tree");
  EXPECT_EQ(s.bark.style, BarkStyle::kBirch);
  EXPECT_EQ(s.leaf.shape, LeafShape::kSpiny);
  const AgeVariant& young = s.age("young");
  EXPECT_DOUBLE_EQ(young.params.scale, 3);
  EXPECT_DOUBLE_EQ(young.params.level[1].branches, 5);
  EXPECT_DOUBLE_EQ(young.params.level[1].length, 0.5);  // kept from the shared entry
  EXPECT_EQ(young.params.shape, 1);
  EXPECT_DOUBLE_EQ(young.params.leaf.rotate, 90);
  EXPECT_DOUBLE_EQ(young.height_min, 1);
  const AgeVariant& adult = s.age("adult");
  EXPECT_EQ(adult.params.level.size(), 3u);  // a third level, copied from the last then merged
  EXPECT_DOUBLE_EQ(adult.params.level[2].branches, 3);
  EXPECT_DOUBLE_EQ(adult.params.level[2].length, 0.5);
  EXPECT_DOUBLE_EQ(s.age("middle").params.scale, 10);
  EXPECT_EQ(adult.params.materials.bark_texture, "bark.png");
  EXPECT_EQ(adult.params.materials.leaf_texture, "leaves.png");
  // Foliage: the card (atlas look and placement), the LAI range and the per-age target.
  EXPECT_DOUBLE_EQ(adult.params.leaf_area_index, 4.5);
  EXPECT_DOUBLE_EQ(adult.params.foliage_zone, 0.4);
  EXPECT_DOUBLE_EQ(young.params.leaf_area_index, 0);
  EXPECT_EQ(s.card.style, CardStyle::kSpray);
  EXPECT_EQ(s.card.elements, 50);
  EXPECT_EQ(s.card.shoots, 3);
  EXPECT_DOUBLE_EQ(s.card.length_m, 0.3);
  EXPECT_DOUBLE_EQ(adult.params.card.aspect, 0.6);
  EXPECT_EQ(adult.params.card.min_layers, 2);
  EXPECT_EQ(adult.params.card.max_layers, 3);
  EXPECT_DOUBLE_EQ(adult.params.card.light_bias, 0.2);
  EXPECT_DOUBLE_EQ(s.lai_min, 2);
  EXPECT_DOUBLE_EQ(s.lai_max, 5);
  EXPECT_EQ(s.lai_source, "d");
}

// The card and LAI blocks: bad values and missing keys name their line.
TEST(Preset, CardAndLeafAreaErrors) {
  EXPECT_EQ(error_of(replace(kGood, "style: spray", "style: fern")),
            "t.yaml:28:16: style: 'fern' is not one of twig, tuft, spray");
  EXPECT_EQ(error_of(replace(kGood, "layers: [2, 3]", "layers: [3, 2]")),
            "t.yaml:28:84: card.layers: expected 1 <= min <= max <= 4");
  EXPECT_EQ(error_of(replace(kGood, "range: [2, 5]", "range: [5, 2]")),
            "t.yaml:29:27: leaf_area_index.range: expected 0 < min < max <= 20");
  EXPECT_EQ(error_of(replace(kGood, "leaf_area_index: { range: [2, 5], source: \"d\" }\n", "")),
            "t.yaml:1:1: the preset: missing required key 'leaf_area_index'");
  EXPECT_EQ(error_of(replace(kGood, "LeafAreaIndex: 4.5", "LeafAreaIndex: 25")),
            "t.yaml:27:78: ages.adult: LeafAreaIndex must be in [0, 20]");
}

TEST(Preset, UnknownKeyIsAnErrorAtItsLine) {
  EXPECT_EQ(error_of(replace(kGood, "{ Branches: 10,", "{ Brances: 10,")),
            "t.yaml:14:9: unknown key 'Brances' in params.levels[1]");
  EXPECT_EQ(error_of(replace(kGood, "  Shape: 1\n", "  Shap: 1\n")),
            "t.yaml:9:3: unknown key 'Shap' in params");
}

TEST(Preset, TypeErrors) {
  EXPECT_EQ(error_of(replace(kGood, "Shape: 1", "Shape: round")),
            "t.yaml:9:10: Shape: expected an integer, got 'round'");
  EXPECT_EQ(error_of(replace(kGood, "Scale: 10", "Scale: tall")),
            "t.yaml:10:10: Scale: expected a number, got 'tall'");
  EXPECT_EQ(error_of(replace(kGood, "foliage: leaves", "foliage: fronds")),
            "t.yaml:3:10: foliage: 'fronds' is not one of leaves, needles");
  EXPECT_EQ(error_of(replace(kGood, "color: [0.9, 0.9, 0.9]", "color: [0.9, 0.9]")),
            "t.yaml:6:32: color: expected [r, g, b] (sRGB, 0..1)");
}

// A value out of range is reported where it was set (here in the shared params, found while
// checking the young variant).
TEST(Preset, RangeErrorPointsAtTheValue) {
  EXPECT_EQ(error_of(replace(kGood, "BranchRatio: 0.4", "BranchRatio: 1.5")),
            "t.yaml:14:49: ages.young: levels[1].BranchRatio must be in (0, 1]");
  EXPECT_EQ(error_of(replace(kGood, "params: { Scale: 3,", "params: { Scale: -3,")),
            "t.yaml:20:22: ages.young: Scale must be in (0, 200]");
  EXPECT_EQ(error_of(replace(kGood, "BranchRatio: 0.4", "BranchRatio: 0.4, ClumpSize: 0")),
            "t.yaml:14:65: ages.young: levels[1].ClumpSize must be in (0, 1]");
}

// The clump parameters (weber_penn.h) are per-level keys like W&P's.
TEST(Preset, ReadsClumps) {
  const SpeciesPreset s = parse_species_preset(
      replace(kGood, "BranchRatio: 0.4", "BranchRatio: 0.4, Clumps: 3, ClumpSize: 0.25, ClumpBase: 0.1"),
      "t.yaml");
  EXPECT_EQ(s.age("middle").params.level[1].clumps, 3);
  EXPECT_DOUBLE_EQ(s.age("middle").params.level[1].clump_size, 0.25);
  EXPECT_DOUBLE_EQ(s.age("middle").params.level[1].clump_base, 0.1);
  EXPECT_EQ(s.age("middle").params.level[0].clumps, 0);
}

// Hem, TrunkUp, ShapeFloor and Pendulous (weber_penn.h) are tree-level keys; an age may set them.
TEST(Preset, ReadsHemTrunkUpShapeFloorAndPendulous) {
  const SpeciesPreset s =
      parse_species_preset(replace(kGood, "params: { Scale: 3,",
                                   "params: { Hem: 0.25, HemV: 0.1, TrunkUp: 0.5, ShapeFloor: 0.05, "
                                   "AttractionUp: -2, Pendulous: 1, Scale: 3,"),
                           "t.yaml");
  EXPECT_DOUBLE_EQ(s.age("young").params.hem, 0.25);
  EXPECT_DOUBLE_EQ(s.age("young").params.hem_v, 0.1);
  EXPECT_DOUBLE_EQ(s.age("young").params.trunk_up, 0.5);
  EXPECT_DOUBLE_EQ(s.age("young").params.shape_floor, 0.05);
  EXPECT_DOUBLE_EQ(s.age("young").params.pendulous, 1.0);
  EXPECT_DOUBLE_EQ(s.age("middle").params.hem, 0.0);
  EXPECT_DOUBLE_EQ(s.age("middle").params.trunk_up, 0.0);
  EXPECT_DOUBLE_EQ(s.age("middle").params.shape_floor, 0.2);
  EXPECT_EQ(error_of(replace(kGood, "params: { Scale: 3,", "params: { Hem: 1.5, Scale: 3,")),
            "t.yaml:20:20: ages.young: Hem must be in [0, 1)");
}

TEST(Preset, MissingPieces) {
  EXPECT_EQ(error_of(replace(kGood, "    height_m: [4, 9]\n", "")),
            "t.yaml:22:5: ages.middle: missing required key 'height_m'");
  EXPECT_EQ(error_of(replace(kGood, "  adult:\n    height_m: [8, 14]\n    source: \"c\"\n", "")),
            "t.yaml:17:3: ages: missing required key 'adult'");
  EXPECT_EQ(error_of(replace(kGood, "height_m: [1, 5]", "height_m: [5, 1]")),
            "t.yaml:18:15: ages.young.height_m: expected 0 < min < max");
}

TEST(Preset, SyntaxErrorAndEmptyFile) {
  EXPECT_EQ(error_of(replace(kGood, "  Scale: 10\n", "  Scale: [10\n")).substr(0, 35),
            "t.yaml:11:9: YAML syntax error: end");
  EXPECT_EQ(error_of(""), "t.yaml:1:1: the preset is empty");
}

TEST(Preset, MissingFile) { EXPECT_THROW(load_species_preset("/nonexistent/x.yaml"), PresetParseError); }

// Fuzz-style: deterministic random edits of a real preset (deleted lines, swapped characters,
// truncation). Every outcome is a preset or a PresetParseError with a file:line:col message —
// never a crash or another exception type.
TEST(Preset, RandomEditsNeverCrash) {
  const std::string good = kGood;
  sylva::test::XorShift64 next(0x2545f4914f6cdd1dull);
  const std::string alphabet = "{}[]:,-#'\"\n 0123456789.aeZ&*!|>";
  int rejected = 0;
  for (int i = 0; i < 1500; ++i) {
    std::string text = good;
    const int edits = 1 + static_cast<int>(next() % 3);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const std::size_t at = next() % text.size();
      switch (next() % 4) {
        case 0:
          text[at] = alphabet[next() % alphabet.size()];
          break;
        case 1:
          text.erase(at, 1 + next() % 20);
          break;
        case 2:
          text.insert(at, 1, alphabet[next() % alphabet.size()]);
          break;
        default:
          text.resize(at);
          break;
      }
    }
    try {
      (void)parse_species_preset(text, "f.yaml");
    } catch (const PresetParseError& e) {
      ++rejected;
      EXPECT_EQ(std::string(e.what()).rfind("f.yaml:", 0), 0u) << e.what();
    }
  }
  EXPECT_GT(rejected, 700);
}

}  // namespace
}  // namespace sylva::generate
