// Issue 14 "The chain per species" and "Compression and size", for the mesh levels the lod
// stage proved (each level's epsilon, delta and switch distance come from its lod.gltf node).
#include "stages/pack/pack_core.h"

#include <stdexcept>

#include "libs/gltf/optimize.h"
#include "libs/gltf/writer.h"
#include "libs/pack/lod_json.h"

namespace sylva::pack {

namespace {

double number(const nlohmann::json& extras, const char* key, const std::string& where) {
  if (!extras.is_object() || !extras.contains(key) || !extras[key].is_number())
    throw std::invalid_argument(where + " has no numeric extras." + key);
  return extras[key].get<double>();
}

void count_primitives(const gltf::Scene& s, LodLevel& l) {
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) {
      const std::size_t n = p.indices.empty() ? p.vertex_count() : p.indices.size();
      if (p.mode == gltf::PrimitiveMode::kTriangles) l.triangles += n / 3;
      if (p.mode == gltf::PrimitiveMode::kLines) l.lines += n / 2;
    }
}

}  // namespace

std::vector<PackedFile> pack_species(const SpeciesInput& in, const PackOptions& options) {
  const gltf::Scene& chain = in.chain;
  if (chain.roots.size() != 1 || chain.roots[0] < 0 || std::size_t(chain.roots[0]) >= chain.nodes.size())
    throw std::invalid_argument("the lod chain has not exactly one root node");
  const gltf::Node& root = chain.nodes[std::size_t(chain.roots[0])];
  const nlohmann::json& ids = root.extensions.is_object()
                                  ? root.extensions.value("MSFT_lod", nlohmann::json())["ids"]
                                  : nlohmann::json();
  if (!ids.is_array() || ids.size() + 1 != in.levels.size())
    throw std::invalid_argument("the lod chain's MSFT_lod names " +
                                std::to_string(ids.is_array() ? ids.size() + 1 : 0) + " levels, but " +
                                std::to_string(in.levels.size()) + " level files were given");
  const nlohmann::json& coverage =
      root.extras.is_object() ? root.extras.value("MSFT_screencoverage", nlohmann::json()) : nlohmann::json();
  if (!coverage.is_array() || coverage.size() != in.levels.size())
    throw std::invalid_argument("the lod chain's root has no MSFT_screencoverage for every level");

  gltf::WriteOptions w;
  w.format = gltf::FileFormat::kGlb;
  w.meshopt = options.compression == Compression::kMeshopt;
  w.draco.enabled = options.compression == Compression::kDraco;
  auto encode = [&](gltf::Scene s) {
    if (options.optimize) gltf::optimize_scene(s);
    nlohmann::json extras = s.extras.is_object() ? s.extras : nlohmann::json::object();
    extras["sylva_stage"] = "pack";
    extras["species"] = in.species;
    s.extras = std::move(extras);
    return gltf::encode(s, w);
  };

  std::vector<PackedFile> out;
  const std::string chain_name = in.species + ".glb";
  out.push_back({chain_name, encode(chain), in.chain_inputs});
  LodDescription d;
  d.species = in.species;
  d.chain = chain_name;
  for (std::size_t i = 0; i < in.levels.size(); ++i) {
    const int node = i == 0 ? chain.roots[0] : ids[i - 1].get<int>();
    if (node < 0 || std::size_t(node) >= chain.nodes.size())
      throw std::invalid_argument("MSFT_lod names node " + std::to_string(node) + ", which does not exist");
    const nlohmann::json& extras = chain.nodes[std::size_t(node)].extras;
    const std::string where = "level " + std::to_string(i) + " (node " + std::to_string(node) + ")";
    LodLevel l;
    l.file = in.species + "_lod" + std::to_string(i) + ".glb";
    l.epsilon_m = number(extras, "epsilon_m", where);
    l.pixel_error_px = number(extras, "pixel_error_px", where);
    l.switch_distance_m = number(extras, "switch_distance_m", where);
    l.screen_coverage = coverage[i].get<double>();
    count_primitives(in.levels[i], l);
    std::string bytes = encode(in.levels[i]);
    l.bytes = bytes.size();
    d.levels.push_back(l);
    out.push_back({l.file, std::move(bytes),
                   i < in.level_inputs.size() ? in.level_inputs[i] : std::vector<std::string>{}});
  }
  out.push_back({in.species + ".lod.json", write_lod_json(d), in.chain_inputs});
  return out;
}

}  // namespace sylva::pack
