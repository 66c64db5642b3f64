// The lod artifact's glTF metadata (chain_gltf.h). The reader trusts nothing: a chain or level
// file may come from anywhere, so every key is checked before it is read and the first problem
// is one sentence naming the level and the key.
#include "libs/lodchain/chain_gltf.h"

namespace sylva::lodchain {

namespace {

using Json = nlohmann::json;

// The keys a packed chain keeps of a level's extras: the level's place in the error model.
constexpr const char* kLevelNumberKeys[] = {"sylva_lod_level", "epsilon_m", "pixel_error_px",
                                            "switch_distance_m"};

double number(const Json& extras, const char* key, const std::string& where) {
  if (!extras.is_object() || !extras.contains(key) || !extras[key].is_number())
    throw ChainGltfError(where + " has no numeric extras." + key);
  return extras[key].get<double>();
}

}  // namespace

Json level_extras(const Level& l) {
  const LevelCounts& c = l.counts;
  return {{"sylva_lod_level", l.sylva_lod_level},
          {"epsilon_m", l.epsilon_m},
          {"pixel_error_px", l.pixel_error_px},
          {"switch_distance_m", l.switch_distance_m},
          {"E1_m", l.e1_m},
          {"E2_m", l.e2_m},
          {"E3_m", l.e3_m},
          {"E4_m", l.e4_m},
          {"E5_m", l.e5_m},
          {"line_alpha", l.line_alpha},
          {"line_alpha_eq12", l.line_alpha_eq12},
          {"needle_line_alpha", l.needle_line_alpha},
          {"needle_line_alpha_eq12", l.needle_line_alpha_eq12},
          {"max_polygon_error_m", l.max_polygon_error_m},
          {"counts",
           {{"quads", c.quads},
            {"triangles", c.triangles},
            {"lines", c.lines},
            {"leaves", c.leaves},
            {"needle_lines", c.needle_lines},
            {"needle_quads", c.needle_quads},
            {"internodes", c.internodes},
            {"branches", c.branches}}}};
}

Json level_number_extras(const Json& extras, std::optional<double> switch_distance_m) {
  Json out = Json::object();
  if (!extras.is_object()) return out;
  for (const char* key : kLevelNumberKeys)
    if (extras.contains(key)) out[key] = extras[key];
  if (switch_distance_m && out.contains("switch_distance_m")) out["switch_distance_m"] = *switch_distance_m;
  return out;
}

Json impostor_level_extras(std::size_t level, const std::string& impostor_kind, double epsilon_m,
                           double pixel_error_px, double switch_distance_m) {
  return {{"sylva_lod_level", level},         {"kind", "impostor"},
          {"impostor_kind", impostor_kind},   {"epsilon_m", epsilon_m},
          {"pixel_error_px", pixel_error_px}, {"switch_distance_m", switch_distance_m}};
}

void link_levels(Json& root_extras, Json& root_extensions, const std::vector<int>& level_nodes,
                 const std::vector<double>& coverage) {
  root_extras["MSFT_screencoverage"] = coverage;
  if (level_nodes.size() >= 2) {
    Json ids = Json::array();
    for (std::size_t i = 1; i < level_nodes.size(); ++i) ids.push_back(level_nodes[i]);
    root_extensions = {{"MSFT_lod", {{"ids", ids}}}};
  }
}

std::vector<ChainLevelNumbers> read_chain_levels(const std::vector<int>& roots, std::size_t node_count,
                                                 std::size_t level_count,
                                                 const std::function<ChainNode(std::size_t)>& node) {
  if (roots.size() != 1 || roots[0] < 0 || std::size_t(roots[0]) >= node_count)
    throw ChainGltfError("the lod chain has not exactly one root node");
  const ChainNode root = node(std::size_t(roots[0]));
  const Json& extensions = *root.extensions;
  const Json& extras = *root.extras;
  const Json no_ids = Json::array();
  const Json& ids = extensions.is_object() && extensions.contains("MSFT_lod")
                        ? extensions["MSFT_lod"].value("ids", no_ids)
                        : no_ids;
  if (!ids.is_array() || ids.size() + 1 != level_count)
    throw ChainGltfError("the lod chain's MSFT_lod names " +
                         std::to_string(ids.is_array() ? ids.size() + 1 : 0) + " levels, but " +
                         std::to_string(level_count) + " level files were given");
  const Json& coverage = extras.is_object() ? extras.value("MSFT_screencoverage", Json()) : Json();
  if (!coverage.is_array() || coverage.size() != level_count)
    throw ChainGltfError("the lod chain's root has no MSFT_screencoverage for every level");
  std::vector<ChainLevelNumbers> out;
  for (std::size_t i = 0; i < level_count; ++i) {
    const int n = i == 0 ? roots[0] : (ids[i - 1].is_number_integer() ? ids[i - 1].get<int>() : -1);
    if (n < 0 || std::size_t(n) >= node_count)
      throw ChainGltfError("MSFT_lod names node " + std::to_string(n) + ", which does not exist");
    const Json& level = *node(std::size_t(n)).extras;
    const std::string where = "level " + std::to_string(i) + " (node " + std::to_string(n) + ")";
    if (!coverage[i].is_number())
      throw ChainGltfError("MSFT_screencoverage[" + std::to_string(i) + "] is not a number");
    ChainLevelNumbers l;
    l.node = n;
    l.epsilon_m = number(level, "epsilon_m", where);
    l.pixel_error_px = number(level, "pixel_error_px", where);
    l.switch_distance_m = number(level, "switch_distance_m", where);
    l.screen_coverage = coverage[i].get<double>();
    out.push_back(l);
  }
  return out;
}

LevelFile parse_level_file(const std::string& text, const std::string& name,
                           const std::function<void(const std::string& uri, LevelResource kind)>& need) {
  LevelFile out;
  try {
    out.gltf = Json::parse(text);
    const Json& buffers = out.gltf.at("buffers");
    if (buffers.size() != 1 || !buffers[0].contains("uri"))
      throw ChainGltfError(name + " must have exactly one external buffer");
    out.buffer_uri = buffers[0]["uri"].get<std::string>();
    need(out.buffer_uri, LevelResource::kBuffer);
    out.buffer_bytes = buffers[0].at("byteLength").get<std::size_t>();
    for (const auto& im : out.gltf.value("images", Json::array())) {
      if (!im.contains("uri")) continue;
      out.image_uris.push_back(im["uri"].get<std::string>());
      need(out.image_uris.back(), LevelResource::kImage);
    }
  } catch (const Json::exception& e) {
    throw ChainGltfError(std::string("unreadable lod output: ") + e.what());
  }
  return out;
}

}  // namespace sylva::lodchain
