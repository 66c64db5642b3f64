// Species preset reader (format in docs/stages/generate.md). Parsing fills plain structs; range
// checks are validate_preset()'s, mapped back to the line that set the offending value.
#include "stages/generate/preset.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <variant>

#include "libs/fileio/read_file.h"

namespace sylva::generate {

namespace {

using Marks = std::map<std::string, YAML::Mark>;

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const YAML::Mark& m, const std::string& msg) const {
    throw PresetParseError(file_ + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1) +
                           ": " + msg);
  }

  // Every key of `map` must be in `known` (and appear once); returns the map.
  void require_map(const YAML::Node& n, const std::string& what) const {
    if (!n.IsMap()) fail(n.Mark(), what + ": expected a mapping");
  }
  template <class F>
  void for_each_key(const YAML::Node& map, const std::string& what, const std::set<std::string>& known,
                    F&& f) const {
    require_map(map, what);
    std::set<std::string> seen;
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      if (!kv.first.IsScalar()) fail(kv.first.Mark(), what + ": keys must be plain names");
      if (!known.count(key)) fail(kv.first.Mark(), "unknown key '" + key + "' in " + what);
      if (!seen.insert(key).second) fail(kv.first.Mark(), "duplicate key '" + key + "' in " + what);
      f(key, kv.second);
    }
  }
  YAML::Node required(const YAML::Node& map, const std::string& key, const std::string& what) const {
    const YAML::Node n = map[key];
    if (!n) fail(map.Mark(), what + ": missing required key '" + key + "'");
    return n;
  }

  double real(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n.Mark(), key + ": expected a number");
    double v;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(n.Mark(), key + ": expected a number, got '" + n.Scalar() + "'");
    }
    if (!std::isfinite(v)) fail(n.Mark(), key + ": expected a finite number, got '" + n.Scalar() + "'");
    return v;
  }
  int integer(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n.Mark(), key + ": expected an integer");
    try {
      return n.as<int>();
    } catch (const YAML::Exception&) {
      fail(n.Mark(), key + ": expected an integer, got '" + n.Scalar() + "'");
    }
  }
  std::string string(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n.Mark(), key + ": expected a string");
    return n.Scalar();
  }
  tree::Color color(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence() || n.size() != 3) fail(n.Mark(), key + ": expected [r, g, b] (sRGB, 0..1)");
    float c[3];
    for (std::size_t i = 0; i < 3; ++i) {
      const double v = real(n[i], key);
      if (v < 0 || v > 1) fail(n[i].Mark(), key + ": colour components must be in [0, 1]");
      c[i] = static_cast<float>(v);
    }
    return {c[0], c[1], c[2]};
  }
  template <class E>
  E choice(const YAML::Node& n, const std::string& key,
           const std::vector<std::pair<std::string, E>>& options) const {
    const std::string s = string(n, key);
    std::string list;
    for (const auto& [name, value] : options) {
      if (name == s) return value;
      list += (list.empty() ? "" : ", ") + name;
    }
    fail(n.Mark(), key + ": '" + s + "' is not one of " + list);
  }

  // A numeric key of a parameter block and the member of `S` it sets (real or integer).
  template <class S>
  struct Field {
    const char* key;
    std::variant<double S::*, int S::*> member;
  };
  template <class S, std::size_t N>
  static std::set<std::string> keys_of(const std::array<Field<S>, N>& fields,
                                       std::initializer_list<const char*> extra = {}) {
    std::set<std::string> keys(extra.begin(), extra.end());
    for (const Field<S>& f : fields) keys.insert(f.key);
    return keys;
  }
  // Sets the member `key` names from `v`; false when `key` is not in `fields`.
  template <class S, std::size_t N>
  bool set_field(const std::array<Field<S>, N>& fields, const std::string& key, const YAML::Node& v,
                 S& s) const {
    for (const Field<S>& f : fields) {
      if (key != f.key) continue;
      if (const auto* d = std::get_if<double S::*>(&f.member))
        s.** d = real(v, key);
      else
        s.*std::get<int S::*>(f.member) = integer(v, key);
      return true;
    }
    return false;
  }

  static constexpr std::array<Field<Preset>, 21> kParams{{
      {"Shape", &Preset::shape},
      {"Levels", &Preset::levels},
      {"Scale", &Preset::scale},
      {"ScaleV", &Preset::scale_v},
      {"BaseSize", &Preset::base_size},
      {"Ratio", &Preset::ratio},
      {"Flare", &Preset::flare},
      {"BaseSplits", &Preset::base_splits},
      {"AttractionUp", &Preset::attraction_up},
      {"TreeShapeExponent", &Preset::tree_shape_exponent},
      {"Leaves", &Preset::leaves},
      {"LeafScale", &Preset::leaf_scale},
      {"LeafScaleX", &Preset::leaf_scale_x},
      {"LeafAreaIndex", &Preset::leaf_area_index},
      {"FoliageZone", &Preset::foliage_zone},
      {"CardScale", &Preset::card_scale},
      {"Hem", &Preset::hem},
      {"HemV", &Preset::hem_v},
      {"TrunkUp", &Preset::trunk_up},
      {"ShapeFloor", &Preset::shape_floor},
      {"Pendulous", &Preset::pendulous},
  }};
  static constexpr std::array<Field<LevelParams>, 17> kLevel{{
      {"Branches", &LevelParams::branches},
      {"Length", &LevelParams::length},
      {"LengthV", &LevelParams::length_v},
      {"Taper", &LevelParams::taper},
      {"SegSplits", &LevelParams::seg_splits},
      {"SplitAngleV", &LevelParams::split_angle_v},
      {"CurveRes", &LevelParams::curve_res},
      {"Curve", &LevelParams::curve},
      {"CurveV", &LevelParams::curve_v},
      {"CurveBack", &LevelParams::curve_back},
      {"DownAngleV", &LevelParams::down_angle_v},
      {"Rotate", &LevelParams::rotate},
      {"RotateV", &LevelParams::rotate_v},
      {"BranchRatio", &LevelParams::branch_ratio},
      {"Clumps", &LevelParams::clumps},
      {"ClumpSize", &LevelParams::clump_size},
      {"ClumpBase", &LevelParams::clump_base},
  }};
  static constexpr std::array<Field<LeafLevelParams>, 4> kLeaf{{
      {"DownAngleV", &LeafLevelParams::down_angle_v},
      {"Rotate", &LeafLevelParams::rotate},
      {"RotateV", &LeafLevelParams::rotate_v},
      {"BranchRatio", &LeafLevelParams::branch_ratio},
  }};

  // `params:` (shared or per age) merged onto `p`; `marks` records where each key was set.
  void apply_params(const YAML::Node& node, Preset& p, Marks& marks, const std::string& what) const {
    static const std::set<std::string> keys = keys_of(kParams, {"levels", "leaf"});
    for_each_key(node, what, keys, [&](const std::string& k, const YAML::Node& v) {
      marks[k] = v.Mark();
      if (set_field(kParams, k, v, p)) return;
      if (k == "leaf") {
        apply_leaf(v, p.leaf, marks, what + ".leaf");
        return;
      }
      // k == "levels"
      if (!v.IsSequence()) fail(v.Mark(), what + ".levels: expected a list (index 0 = trunk)");
      if (v.size() > 8) fail(v.Mark(), what + ".levels: at most 8 levels");
      if (p.level.size() < v.size())
        p.level.resize(v.size(), p.level.empty() ? LevelParams{} : p.level.back());
      for (std::size_t i = 0; i < v.size(); ++i)
        apply_level(v[i], p.level[i], marks, "levels[" + std::to_string(i) + "]", what);
    });
  }

  void apply_level(const YAML::Node& node, LevelParams& l, Marks& marks, const std::string& key,
                   const std::string& what) const {
    static const std::set<std::string> keys = keys_of(kLevel);
    for_each_key(node, what + "." + key, keys, [&](const std::string& k, const YAML::Node& v) {
      marks[key + "." + k] = v.Mark();
      set_field(kLevel, k, v, l);
    });
  }

  void apply_leaf(const YAML::Node& node, LeafLevelParams& l, Marks& marks, const std::string& what) const {
    static const std::set<std::string> keys = keys_of(kLeaf);
    for_each_key(node, what, keys, [&](const std::string& k, const YAML::Node& v) {
      marks["leaf." + k] = v.Mark();
      set_field(kLeaf, k, v, l);
    });
  }

  void textures(const YAML::Node& node, SpeciesPreset& s) const {
    for_each_key(node, "textures", {"bark", "leaf"}, [&](const std::string& k, const YAML::Node& v) {
      if (k == "bark") {
        for_each_key(v, "textures.bark", {"style", "color", "dark", "lower_tint"},
                     [&](const std::string& bk, const YAML::Node& bv) {
                       if (bk == "lower_tint") {
                         for_each_key(bv, "textures.bark.lower_tint", {"color", "below", "above"},
                                      [&](const std::string& tk, const YAML::Node& tv) {
                                        if (tk == "color")
                                          tint_.color = color(tv, tk);
                                        else if (tk == "below")
                                          tint_.below = real(tv, tk);
                                        else
                                          tint_.above = real(tv, tk);
                                        tint_.mark = bv.Mark();
                                      });
                         required(bv, "color", "textures.bark.lower_tint");
                         required(bv, "below", "textures.bark.lower_tint");
                         required(bv, "above", "textures.bark.lower_tint");
                         if (!(tint_.below >= 0 && tint_.below <= tint_.above && tint_.above <= 1))
                           fail(bv.Mark(),
                                "textures.bark.lower_tint: expected 0 <= below <= above <= 1 (fractions of "
                                "the height)");
                       } else if (bk == "style")
                         s.bark.style = choice<BarkStyle>(bv, "style",
                                                          {{"fissured", BarkStyle::kFissured},
                                                           {"smooth", BarkStyle::kSmooth},
                                                           {"birch", BarkStyle::kBirch},
                                                           {"scaly", BarkStyle::kScaly}});
                       else if (bk == "color")
                         s.bark.color = color(bv, bk);
                       else
                         s.bark.dark = color(bv, bk);
                     });
      } else {
        for_each_key(v, "textures.leaf", {"shape", "color", "vein"},
                     [&](const std::string& lk, const YAML::Node& lv) {
                       if (lk == "shape")
                         s.leaf.shape = choice<LeafShape>(lv, "shape",
                                                          {{"lobed", LeafShape::kLobed},
                                                           {"ovate", LeafShape::kOvate},
                                                           {"palmate", LeafShape::kPalmate},
                                                           {"spiny", LeafShape::kSpiny},
                                                           {"lanceolate", LeafShape::kLanceolate},
                                                           {"needle", LeafShape::kNeedle}});
                       else if (lk == "color")
                         s.leaf.color = color(lv, lk);
                       else
                         s.leaf.vein = color(lv, lk);
                     });
      }
    });
  }

  // `card:` — the twig or shoot a card shows (atlas) and how cards are placed (Preset::card).
  void card(const YAML::Node& node, SpeciesPreset& s, CardShape& shape) const {
    static const std::set<std::string> keys = {"style",  "length_m",  "aspect",         "elements",
                                               "shoots", "petiole",   "leaf_angle_deg", "cluster",
                                               "layers", "light_bias"};
    for_each_key(node, "card", keys, [&](const std::string& k, const YAML::Node& v) {
      auto in = [&](double x, double lo, double hi, const char* rule) {
        if (!(x >= lo && x <= hi)) fail(v.Mark(), "card." + k + ": must be " + rule);
        return x;
      };
      if (k == "style") {
        s.card.style = choice<CardStyle>(
            v, k, {{"twig", CardStyle::kTwig}, {"tuft", CardStyle::kTuft}, {"spray", CardStyle::kSpray}});
      } else if (k == "length_m") {
        shape.length = s.card.length_m = in(real(v, k), 0.01, 5, "in [0.01, 5]");
      } else if (k == "aspect") {
        shape.aspect = s.card.aspect = in(real(v, k), 0.1, 4, "in [0.1, 4]");
      } else if (k == "elements") {
        s.card.elements = static_cast<int>(in(integer(v, k), 1, 20000, "1..20000"));
      } else if (k == "shoots") {
        s.card.shoots = static_cast<int>(in(integer(v, k), 0, 12, "0..12"));
      } else if (k == "petiole") {
        s.card.petiole = in(real(v, k), 0, 1, "in [0, 1]");
      } else if (k == "leaf_angle_deg") {
        s.card.leaf_angle_deg = in(real(v, k), 0, 90, "in [0, 90]");
      } else if (k == "cluster") {
        s.card.cluster = in(real(v, k), 0, 1, "in [0, 1]");
      } else if (k == "light_bias") {
        shape.light_bias = in(real(v, k), 0, 1, "in [0, 1]");
      } else {
        if (!v.IsSequence() || v.size() != 2) fail(v.Mark(), "card.layers: expected [min, max]");
        shape.min_layers = integer(v[0], k);
        shape.max_layers = integer(v[1], k);
        if (!(shape.min_layers >= 1 && shape.min_layers <= shape.max_layers && shape.max_layers <= 4))
          fail(v.Mark(), "card.layers: expected 1 <= min <= max <= 4");
      }
    });
  }

  void lai(const YAML::Node& node, SpeciesPreset& s) const {
    for_each_key(node, "leaf_area_index", {"range", "source"},
                 [&](const std::string& k, const YAML::Node& v) {
                   if (k == "source") {
                     s.lai_source = string(v, k);
                   } else {
                     if (!v.IsSequence() || v.size() != 2)
                       fail(v.Mark(), "leaf_area_index.range: expected [min, max]");
                     s.lai_min = real(v[0], k);
                     s.lai_max = real(v[1], k);
                     if (!(s.lai_min > 0 && s.lai_min < s.lai_max && s.lai_max <= 20))
                       fail(v.Mark(), "leaf_area_index.range: expected 0 < min < max <= 20");
                   }
                 });
    required(node, "range", "leaf_area_index");
    required(node, "source", "leaf_area_index");
  }

  SpeciesPreset parse(const YAML::Node& root) const {
    if (!root.IsMap()) fail(root.Mark(), "a species preset must be a mapping");
    SpeciesPreset s;
    Preset base;
    base.level.assign(1, LevelParams{});
    Marks base_marks;
    YAML::Node ages_node;
    CardShape shape;
    YAML::Node lai_node;
    for_each_key(
        root, "the preset",
        {"species", "name", "foliage", "sources", "textures", "card", "leaf_area_index", "params", "ages"},
        [&](const std::string& k, const YAML::Node& v) {
          if (k == "species") {
            s.species = string(v, k);
            if (s.species.empty() ||
                s.species.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") != std::string::npos)
              fail(v.Mark(), "species: must be a name of [a-z_], got '" + s.species + "'");
          } else if (k == "name") {
            s.name = string(v, k);
          } else if (k == "foliage") {
            base.foliage =
                choice<Foliage>(v, k, {{"leaves", Foliage::kLeaves}, {"needles", Foliage::kNeedles}});
          } else if (k == "sources") {
            if (!v.IsSequence()) fail(v.Mark(), "sources: expected a list of strings");
            for (const auto& e : v) s.sources.push_back(string(e, k));
          } else if (k == "textures") {
            textures(v, s);
          } else if (k == "card") {
            card(v, s, shape);
          } else if (k == "leaf_area_index") {
            lai(v, s);
          } else if (k == "params") {
            apply_params(v, base, base_marks, "params");
          } else {
            ages_node = v;
          }
        });
    required(root, "species", "the preset");
    required(root, "foliage", "the preset");
    required(root, "params", "the preset");
    required(root, "ages", "the preset");
    required(root, "card", "the preset");
    required(root, "leaf_area_index", "the preset");
    base.card = shape;
    base.bark_tint = srgb_to_linear(tint_.color);
    base.bark_tint_from = tint_.below;
    base.bark_tint_to = tint_.above;
    s.card.leaf_length_m = base.leaf_scale;
    s.card.leaf_width = base.leaf_scale_x;
    for_each_key(ages_node, "ages", {"young", "middle", "adult"},
                 [](const std::string&, const YAML::Node&) {});
    for (const char* age : kAgeNames) {
      const YAML::Node a = required(ages_node, age, "ages");
      const std::string what = std::string("ages.") + age;
      AgeVariant v;
      v.age = age;
      v.params = base;
      Marks marks = base_marks;
      bool have_height = false;
      for_each_key(a, what, {"height_m", "source", "params"}, [&](const std::string& k, const YAML::Node& n) {
        if (k == "height_m") {
          if (!n.IsSequence() || n.size() != 2)
            fail(n.Mark(), what + ".height_m: expected [min, max] in metres");
          v.height_min = real(n[0], "height_m");
          v.height_max = real(n[1], "height_m");
          if (!(v.height_min > 0 && v.height_min < v.height_max))
            fail(n.Mark(), what + ".height_m: expected 0 < min < max");
          have_height = true;
        } else if (k == "source") {
          v.source = string(n, k);
        } else {
          apply_params(n, v.params, marks, what + ".params");
        }
      });
      if (!have_height) fail(a.Mark(), what + ": missing required key 'height_m'");
      if (v.source.empty())
        fail(a.Mark(), what + ": missing required key 'source' (where the figures come from)");
      try {
        validate_preset(v.params);
      } catch (const PresetError& e) {
        auto it = marks.find(e.key());
        fail(it != marks.end() ? it->second : a.Mark(), what + ": " + e.what());
      }
      v.params.materials.bark_texture = "bark.png";
      v.params.materials.leaf_texture = "leaves.png";
      v.params.materials.bark_color = srgb_to_linear(s.bark.color);
      v.params.materials.leaf_color = srgb_to_linear(s.leaf.color);
      s.ages.push_back(std::move(v));
    }
    return s;
  }

 private:
  std::string file_;
  struct Tint {
    tree::Color color{1, 1, 1};
    double below = 0, above = 0;
    YAML::Mark mark;
  };
  mutable Tint tint_;
};

}  // namespace

const AgeVariant& SpeciesPreset::age(std::string_view name) const {
  for (const AgeVariant& a : ages)
    if (a.age == name) return a;
  throw std::out_of_range("no age variant '" + std::string(name) + "'");
}

SpeciesPreset parse_species_preset(std::string_view yaml_text, const std::string& file) {
  Reader r(file);
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::ParserException& e) {
    r.fail(e.mark, "YAML syntax error: " + e.msg);
  }
  if (!root || root.IsNull()) throw PresetParseError(file + ":1:1: the preset is empty");
  try {
    return r.parse(root);
  } catch (const YAML::Exception& e) {  // anything yaml-cpp raises while we walk the tree
    r.fail(e.mark, e.msg);
  }
}

SpeciesPreset load_species_preset(const std::filesystem::path& path) {
  std::string text;
  try {
    text = fileio::read_file(path);
  } catch (const fileio::FileReadError& e) {
    throw PresetParseError(e.what());
  }
  return parse_species_preset(text, path.string());
}

std::vector<std::filesystem::path> species_preset_files(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".yaml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace sylva::generate
