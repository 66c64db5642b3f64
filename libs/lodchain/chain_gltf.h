// The lod artifact's glTF metadata, its one reader and writer (docs/formats.md, docs/stages/lod.md
// "Outputs"): a level's numbers in the extras of its node and mesh, the MSFT_lod links on a
// chain's root node (MSFT_lod ids and extras.MSFT_screencoverage, Microsoft's MSFT_lod
// extension), and a level file's external buffer and images. The lod stage writes them; the pack
// stage reads lod.gltf and writes its own MSFT_lod chain with them; the forest stage reads the
// level files.
//
// Works on the JSON values of glTF nodes (gltf::Node::extras and ::extensions hold nlohmann::json),
// so it needs no glTF library. Numbers keep their JSON types: the bytes a glTF writer makes of
// these values are the lod stage's and the pack stage's, byte for byte.
#pragma once

#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/lodchain/lod_chain.h"

namespace sylva::lodchain {

// A chain's or a level file's metadata is not what the lod stage writes. Derives from
// std::invalid_argument, as the pack stage's other input errors.
class ChainGltfError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// --- Writing ---

// A level's extras (on its node and its mesh): sylva_lod_level, epsilon_m, pixel_error_px,
// switch_distance_m, E1_m..E5_m, the four line alphas, max_polygon_error_m and counts: the numbers
// of `level` that lod.json states too (not its files, its coverage or its cards).
nlohmann::json level_extras(const Level& level);

// The extras a level node of a packed chain keeps of a level's `extras`: sylva_lod_level,
// epsilon_m, pixel_error_px and switch_distance_m, those present (an empty object when none, or
// when `extras` is not an object); switch_distance_m, when present, becomes `switch_distance_m`
// when that is given.
nlohmann::json level_number_extras(const nlohmann::json& extras,
                                   std::optional<double> switch_distance_m = {});

// An impostor level's node extras in a packed chain: sylva_lod_level = `level`, kind "impostor",
// impostor_kind, epsilon_m, pixel_error_px, switch_distance_m.
nlohmann::json impostor_level_extras(std::size_t level, const std::string& impostor_kind, double epsilon_m,
                                     double pixel_error_px, double switch_distance_m);

// Links a chain's levels on its root node (MSFT_lod): root_extras.MSFT_screencoverage =
// `coverage` (one value per level, finest first; root_extras is an object or null), and with two
// levels or more root_extensions = {"MSFT_lod": {"ids": level_nodes[1..]}} (level_nodes[0] is the
// root itself; with one level root_extensions is left as it is).
void link_levels(nlohmann::json& root_extras, nlohmann::json& root_extensions,
                 const std::vector<int>& level_nodes, const std::vector<double>& coverage);

// --- Reading ---

// A node of the chain being read: its extras and extensions (not null pointers).
struct ChainNode {
  const nlohmann::json* extras = nullptr;
  const nlohmann::json* extensions = nullptr;
};

// What a chain states of its level i: its node, its numbers and its MSFT_screencoverage value.
struct ChainLevelNumbers {
  int node = -1;
  double epsilon_m = 0, pixel_error_px = 0, switch_distance_m = 0, screen_coverage = 0;
};

// The levels of an MSFT_lod chain whose scene has root nodes `roots`, `node_count` nodes (node(i)
// gives node i) and `level_count` levels: level 0 is the one root, level i > 0 the root's MSFT_lod
// ids[i - 1]. Throws ChainGltfError when the scene has not exactly one root, the ids do not name
// level_count - 1 existing nodes, the root has no MSFT_screencoverage number per level, or a level's
// node has no numeric extras epsilon_m, pixel_error_px and switch_distance_m (the first problem, in
// level order; the messages are the pack stage's).
std::vector<ChainLevelNumbers> read_chain_levels(const std::vector<int>& roots, std::size_t node_count,
                                                 std::size_t level_count,
                                                 const std::function<ChainNode(std::size_t)>& node);

// A level file (lod<i>.gltf) as its readers need it: its glTF JSON, its one external buffer
// (lod<i>.bin, shared with lod.gltf) and the images it names by uri.
struct LevelFile {
  nlohmann::json gltf;
  std::string buffer_uri;
  std::size_t buffer_bytes = 0;         // the buffer's byteLength
  std::vector<std::string> image_uris;  // in the file's order
};
enum class LevelResource { kBuffer, kImage };

// Parses level file `name`. need(uri, kind) is called for the buffer, before its byteLength is
// read, and then for each image with a uri, in order: the reader checks there that the file
// exists beside it (and may throw). Throws ChainGltfError("<name> must have exactly one external
// buffer"), or ChainGltfError("unreadable lod output: <JSON error>") when the text is not JSON or
// a value has the wrong type.
LevelFile parse_level_file(const std::string& text, const std::string& name,
                           const std::function<void(const std::string& uri, LevelResource kind)>& need);

}  // namespace sylva::lodchain
