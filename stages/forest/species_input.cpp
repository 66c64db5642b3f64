// The forest reads the lod stage's files only through libs/lodchain and the impostor's through
// libs/impostor; every file a level names must be in the artifact (the forest passes them on
// under the species' prefix), so a missing one fails here, naming the input.
#include "stages/forest/species_input.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "libs/lodchain/chain_gltf.h"

namespace sylva::forest {

namespace {

using nlohmann::json;

// Triangles, lines or points of the level's one mesh.
std::size_t primitive_count(const json& g) {
  std::size_t n = 0;
  for (const auto& p : g.at("meshes").at(0).at("primitives")) {
    const int mode = p.value("mode", 4);
    const std::size_t per = mode == 4 ? 3 : mode == 1 ? 2 : 1;
    const std::size_t count =
        p.contains("indices")
            ? g.at("accessors").at(p["indices"].get<std::size_t>()).at("count").get<std::size_t>()
            : g.at("accessors")
                  .at(p.at("attributes").at("POSITION").get<std::size_t>())
                  .at("count")
                  .get<std::size_t>();
    n += count / per;
  }
  return n;
}

// Level 0's bounds: the POSITION accessors' min and max.
Box3 position_bounds(const json& g, const std::string& what) {
  Box3 b{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (const auto& p : g.at("meshes").at(0).at("primitives")) {
    const json& a = g.at("accessors").at(p.at("attributes").at("POSITION").get<std::size_t>());
    if (!a.contains("min") || !a.contains("max"))
      throw StageError(what + ": a POSITION accessor has no min/max");
    for (std::size_t k = 0; k < 3; ++k) {
      b.min[k] = std::min(b.min[k], a["min"][k].get<double>());
      b.max[k] = std::max(b.max[k], a["max"][k].get<double>());
    }
  }
  if (!(b.min[0] <= b.max[0])) throw StageError(what + ": the level mesh has no positions");
  return b;
}

}  // namespace

SpeciesInput read_species(const StageContext& ctx, const InputArtifact& in, const std::string& name) {
  SpeciesInput s;
  s.node = in.node;
  const ArtifactFile* lj = in.file(lodchain::kSummaryFile);
  if (!lj) throw StageError("input '" + in.node + "' has no lod.json");
  try {
    s.chain = lodchain::parse_lod_chain(ctx.read_input(*lj), lj->path.string());  // at least one level
  } catch (const lodchain::LodChainFormatError& e) {
    throw StageError("input '" + in.node + "': " + e.what());
  }
  try {
    for (std::size_t i = 0; i < s.chain.levels.size(); ++i) {
      const std::string& file = s.chain.levels[i].file;
      const ArtifactFile* f = in.file(file);
      if (!f) throw StageError("input '" + in.node + "' has no " + file + " though lod.json lists it");
      // The level file through libs/lodchain: its one buffer and its images, each checked here
      // to be in the artifact as it is named.
      lodchain::LevelFile level = lodchain::parse_level_file(
          ctx.read_input(*f), file, [&](const std::string& uri, lodchain::LevelResource kind) {
            const ArtifactFile* a = in.file(uri);
            if (kind == lodchain::LevelResource::kBuffer) {
              if (!a)
                throw StageError("input '" + in.node + "' has no " + uri + " though " + file + " uses it");
              s.level_bins.push_back(a);
            } else {
              if (!a) throw StageError("input '" + in.node + "' has no image " + uri);
              if (std::find(s.images.begin(), s.images.end(), a) == s.images.end()) s.images.push_back(a);
            }
          });
      LevelSource src;
      src.gltf = std::move(level.gltf);
      src.bin_name = name + "_" + level.buffer_uri;
      src.bin_bytes = level.buffer_bytes;
      src.image_prefix = name + "_";
      s.primitives.push_back(primitive_count(src.gltf));
      if (i == 0) s.bounds = position_bounds(src.gltf, "input '" + in.node + "': " + file);
      s.levels.push_back(std::move(src));
    }
  } catch (const lodchain::ChainGltfError& e) {
    throw StageError("input '" + in.node + "': " + e.what());
  } catch (const json::exception& e) {
    throw StageError("input '" + in.node + "': unreadable lod output: " + e.what());
  }
  return s;
}

void read_impostor(const StageContext& ctx, const InputArtifact& in, const std::string& name,
                   SpeciesInput& s) {
  const ArtifactFile* ij = in.file(impostor::kImpostorJsonFile);
  const ArtifactFile* glb = in.file(impostor::kImpostorGlbFile);
  if (!ij || !glb)
    throw StageError("input '" + in.node + "' (impostor) has no impostor.json and impostor.glb");
  try {
    const impostor::ImpostorInfo info =
        impostor::parse_impostor_json(ctx.read_input(*ij), in.node + "/impostor.json");
    s.impostor_epsilon_m = info.error.epsilon_m();
    if (!(info.switch_distance_m > 0))
      throw StageError("input '" + in.node +
                       "' (impostor): impostor.json records no switch distance (switch_distance_m 0)");
    s.impostor_switch_distance_m = info.switch_distance_m;
    s.impostor_pixel_error_px = info.pixel_error_px;
    s.impostor_camera = info.camera;
    if (info.kind != impostor::Kind::kBillboards) {
      s.octahedral = true;
      s.color_map = in.file(info.color_map);
      s.normal_depth_map = in.file(info.normal_depth_map);
      if (!s.color_map || !s.normal_depth_map)
        throw StageError("input '" + in.node + "' (impostor) has no " + info.color_map + " and " +
                         info.normal_depth_map + " though impostor.json names them");
      s.impostor_info = info;
      s.impostor_info.color_map = name + "_impostor_color.png";
      s.impostor_info.normal_depth_map = name + "_impostor_normal_depth.png";
    }
  } catch (const impostor::ImpostorFormatError& e) {
    throw StageError(e.what());
  }
  try {
    s.impostor = impostor_level_source(ctx.read_input(*glb), name, "input '" + in.node + "': impostor.glb");
  } catch (const std::invalid_argument& e) {
    throw StageError(e.what());
  }
  s.primitives.push_back(primitive_count(s.impostor.source.gltf));
  s.has_impostor = true;
}

}  // namespace sylva::forest
