// Species presets: the YAML files under configs/species/ read into plain structs.
// Seed: Nystad 2010, Appendix A (every parameter key is a thesis/Weber–Penn parameter name).
//
// One file holds one species with three age variants (young, middle, adult). A variant is the
// shared `params` with the age's `params` merged over it (per-level entries merge by index), and
// states the height range a generated tree must fall in plus where the figures come from.
// Format: docs/stages/generate.md, "Preset files". Every error names the file and the 1-based
// line:column of the offending YAML node; unknown keys are errors (a misspelt parameter must not
// be silently ignored).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "stages/generate/card_atlas.h"
#include "stages/generate/textures.h"
#include "stages/generate/weber_penn.h"

namespace sylva::generate {

inline constexpr const char* kAgeNames[] = {"young", "middle", "adult"};

struct AgeVariant {
  std::string age;        // young | middle | adult
  Preset params;          // merged and validated
  double height_min = 0;  // m, expected height range of generated trees
  double height_max = 0;
  std::string source;  // where this age's figures come from
};

struct SpeciesPreset {
  std::string species;  // file-name stem, e.g. "oak"
  std::string name;     // e.g. "Pedunculate oak (Quercus robur)"
  std::vector<std::string> sources;
  BarkLook bark;
  LeafLook leaf;
  CardLook card;                    // the `card:` block (the atlas drawing; placement in Preset::card)
  double lai_min = 0, lai_max = 0;  // leaf_area_index.range: the published range
  std::string lai_source;           // leaf_area_index.source
  std::vector<AgeVariant> ages;     // in kAgeNames order

  const AgeVariant& age(std::string_view name) const;  // throws std::out_of_range
};

// "<file>:<line>:<col>: <message>".
class PresetParseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses preset text; `file` is used in messages only.
SpeciesPreset parse_species_preset(std::string_view yaml_text, const std::string& file);
// Reads and parses a file (PresetParseError "<file>: cannot read" if it cannot be read).
SpeciesPreset load_species_preset(const std::filesystem::path& path);
// The preset files of a folder (its `*.yaml`, e.g. configs/species), sorted by path; throws
// std::filesystem::filesystem_error if the folder cannot be listed.
std::vector<std::filesystem::path> species_preset_files(const std::filesystem::path& dir);

}  // namespace sylva::generate
