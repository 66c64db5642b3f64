// The adapter of stage `forest`: reads the species' lod artifacts (lod.json through libs/lodchain, the level
// glTF files: their bounding boxes and LOD metadata, never their code), the optional maps and CSV, runs the
// layout core (layout.h), groups the trees (hierarchy.h), and writes instances.json (+ instances.bin), each
// species' level files, one glTF per tile and level, tileset.json and the forest camera set.
// docs/stages/forest.md lists every parameter and file.
#include "stages/forest/forest_stage.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "libs/gltf/writer.h"
#include "libs/impostor/impostor_json.h"
#include "libs/lodchain/chain_gltf.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/lodmodel/lod_model.h"
#include "stages/forest/field_io.h"
#include "stages/forest/forest_cameras.h"
#include "stages/forest/forest_info.h"
#include "stages/forest/ground.h"
#include "stages/forest/hierarchy.h"
#include "stages/forest/impostor_level.h"
#include "stages/forest/layout.h"
#include "stages/forest/positions_csv.h"
#include "stages/forest/species_input.h"
#include "stages/forest/tile_gltf.h"
#include "stages/forest/tileset.h"

namespace sylva {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace forest;

std::vector<double> reals(const Value& v) {
  std::vector<double> out;
  for (const Value& e : v.as_list()) out.push_back(e.as_real());
  return out;
}

// x, z pairs (an even count: forest_param_problems).
std::vector<Point2> points_of(const Value& v) {
  const std::vector<double> r = reals(v);
  std::vector<Point2> out;
  for (std::size_t i = 0; i + 1 < r.size(); i += 2) out.push_back({r[i], r[i + 1]});
  return out;
}

// species[i].impostor_parallax (checked by forest_param_problems: pairs, distances increasing,
// steps integers 0..64), for an octahedral impostor only.
std::vector<ParallaxStep> parallax_table(const Value& v, const std::string& species, bool octahedral) {
  const std::vector<double> r = reals(v);
  if (r.empty()) return {};
  if (!octahedral)
    throw StageError("species '" + species +
                     "': impostor_parallax needs a (hemi-)octahedral impostor input for the species");
  std::vector<ParallaxStep> out;
  for (std::size_t k = 0; k + 1 < r.size(); k += 2) out.push_back({r[k], int(r[k + 1])});
  return out;
}

// The node's lod and impostor inputs, in `needs` order, checked against the parameters: the
// checks a recipe's loader ran already (StageInfo::check, check_inputs), for nodes run another way.
struct ForestInputs {
  std::vector<const InputArtifact*> lods, impostors;
};
ForestInputs check_inputs(const StageContext& ctx) {
  if (const auto problems = forest_param_problems(ctx.params()); !problems.empty())
    throw StageError(param_problem_text(problems.front()));
  ForestInputs in;
  for (const InputArtifact& a : ctx.inputs()) (a.type == "lod" ? in.lods : in.impostors).push_back(&a);
  if (!in.impostors.empty() && in.impostors.size() != in.lods.size())
    throw StageError("the node needs " + std::to_string(in.lods.size()) + " lod inputs and " +
                     std::to_string(in.impostors.size()) +
                     " impostor inputs: give every species an impostor (the i-th impostor input is the "
                     "i-th lod input's species) or none");
  std::vector<std::string> types;
  for (const InputArtifact& a : ctx.inputs()) types.push_back(a.type);
  if (const auto problems = forest_input_problems(ctx.params(), types); !problems.empty())
    throw StageError(param_problem_text(problems.front()));
  return in;
}

// The layout rule of one species: its `species` entry `sp` and the box of its level 0 (`bounds`).
SpeciesRule species_rule(const Value::Object& sp, const Box3& bounds) {
  SpeciesRule r;
  r.name = sp.at("name").as_string();
  r.bounds = bounds;
  r.density_per_ha = sp.at("density_per_ha").as_real();
  auto range = [&](const char* key) {
    const auto v = reals(sp.at(key));
    return Point2{v[0], v[1]};
  };
  r.scale_x = range("scale_x");
  r.scale_y = range("scale_y");
  r.scale_z = range("scale_z");
  const auto rot = reals(sp.at("base_rotation_deg"));
  r.base_rotation_deg = {rot[0], rot[1], rot[2]};
  r.base_translation_y_m = sp.at("base_translation_y_m").as_real();
  r.random_yaw = sp.at("random_yaw").as_bool();
  r.max_slope_deg = sp.at("max_slope_deg").as_real();
  r.min_altitude_m = sp.at("min_altitude_m").as_real();
  r.max_altitude_m = sp.at("max_altitude_m").as_real();
  r.min_spacing_m = sp.at("min_spacing_m").as_real();
  return r;
}

// The terrain (height_map over terrain_extent_m, height_range_m) and the density map, when given.
void read_maps(StageContext& ctx, LayoutParams& lp) {
  try {
    if (!ctx.string("height_map").empty()) {
      std::vector<double> e = reals(ctx.param("terrain_extent_m"));
      if (e.empty()) e = {-0.5 * lp.width_m, -0.5 * lp.depth_m, 0.5 * lp.width_m, 0.5 * lp.depth_m};
      lp.terrain.field = read_field(ctx.read_param_file("height_map"), ctx.param_file("height_map").string(),
                                    e[0], e[1], e[2], e[3]);
      const auto hr = reals(ctx.param("height_range_m"));
      lp.terrain.height_min = hr[0];
      lp.terrain.height_max = hr[1];
    }
    if (!ctx.string("density_map").empty())
      lp.density = read_field(ctx.read_param_file("density_map"), ctx.param_file("density_map").string(),
                              -0.5 * lp.width_m, -0.5 * lp.depth_m, 0.5 * lp.width_m, 0.5 * lp.depth_m);
  } catch (const std::runtime_error& e) {
    if (dynamic_cast<const StageError*>(&e)) throw;
    throw StageError(e.what());
  }
}

// The user's placements: exclusion polygons, rows (species by name among `names`) and the
// explicit positions' CSV.
void read_placements(StageContext& ctx, const std::vector<std::string>& names, LayoutParams& lp) {
  const Value::List& ex = ctx.param("exclusions").as_list();
  for (std::size_t i = 0; i < ex.size(); ++i)
    lp.exclusions.push_back(points_of(ex[i].as_object().at("points")));
  const Value::List& rows = ctx.param("rows").as_list();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Value::Object& r = rows[i].as_object();
    const std::string& sp = r.at("species").as_string();
    const auto it = std::find(names.begin(), names.end(), sp);
    lp.rows.push_back({std::uint32_t(it - names.begin()), points_of(r.at("points")),
                       r.at("spacing_m").as_real(), r.at("jitter_m").as_real()});
  }
  if (!ctx.string("positions").empty()) {
    const fs::path p = ctx.param_file("positions");
    try {
      lp.explicit_trees = parse_positions_csv(ctx.read_param_file("positions"), names, p.filename().string());
    } catch (const std::invalid_argument& e) {
      throw StageError(e.what());
    }
  }
}

// Species `name` as instances.json states it: its chain's levels (files named <name>_lod<l>.gltf)
// and, with an impostor, the impostor level last, its distances moved into the chain's terms.
Species forest_species(const std::string& name, const SpeciesInput& in, const SpeciesRule& rule) {
  Species sp;
  sp.name = name;
  sp.source = in.chain.tree;
  sp.bounds = in.bounds;
  sp.base_rotation_deg = rule.base_rotation_deg;
  sp.base_translation_y_m = rule.base_translation_y_m;
  sp.pixel_error_px = in.chain.pixel_error_px;
  sp.fov_y_deg = in.chain.camera_fov_y_deg;
  sp.height_px = in.chain.camera_height_px;
  for (std::size_t l = 0; l < in.chain.levels.size(); ++l)
    sp.levels.push_back({name + "_lod" + std::to_string(l) + ".gltf",
                         in.chain.levels[l].epsilon_m,
                         in.chain.levels[l].switch_distance_m,
                         in.primitives[l],
                         false,
                         "",
                         {}});
  if (in.has_impostor) {
    // Distances in impostor.json's terms (its delta and camera) move into the chain's.
    auto chain_terms = [&](double d) {
      return impostor_switch_distance_m(d, in.impostor_camera, in.impostor_pixel_error_px,
                                        lodmodel::camera_from_degrees(sp.fov_y_deg, sp.height_px),
                                        sp.pixel_error_px);
    };
    sp.levels.push_back({name + "_impostor.gltf",
                         in.impostor_epsilon_m,
                         chain_terms(in.impostor_switch_distance_m),
                         in.primitives.back(),
                         true,
                         in.octahedral ? name + "_impostor.json" : "",
                         {}});
    for (const ParallaxStep& p : in.parallax)
      sp.levels.back().parallax.push_back({chain_terms(p.from_m), p.steps});
  }
  return sp;
}

// The placed trees as instances, grouped into tiles and the spatial hierarchy by the boxes of
// the drawn trees (the asset's own box transformed).
void add_instances(Forest& f, const LayoutResult& layout, StageContext& ctx) {
  std::vector<Box3> boxes;
  for (std::size_t i = 0; i < layout.trees.size(); ++i) {
    const PlacedTree& t = layout.trees[i];
    f.instances.push_back({std::uint32_t(i), t.species, 0, t.position, t.yaw_rad, t.scale});
    boxes.push_back(transform_box(instance_matrix(f.species[t.species], f.instances.back()),
                                  f.species[t.species].bounds));
  }
  ctx.check_cancelled();
  f.tiles = build_tiles(f.instances, boxes, f.extent_min, f.tile_size_m);
  f.hierarchy = build_hierarchy(boxes, f.nodes_per_node);
}

// ground.glb over the forest's extent; returns its bounds (for the tileset's root).
Box3 write_ground(StageContext& ctx, const Forest& f, const Terrain& terrain) {
  const gltf::Scene ground = ground_scene(terrain, f.extent_min, f.extent_max);
  ctx.write_output(f.ground, gltf::encode(ground));
  Box3 ground_bounds{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  const std::vector<float>& gp = ground.meshes[0].primitives[0].positions;
  for (std::size_t i = 0; i < gp.size(); ++i) {
    ground_bounds.min[i % 3] = std::min(ground_bounds.min[i % 3], double(gp[i]));
    ground_bounds.max[i % 3] = std::max(ground_bounds.max[i % 3], double(gp[i]));
  }
  return ground_bounds;
}

// Each species' level files (glTF rewritten, buffers and images passed on under the species'
// prefix) and impostor files; returns the most levels a species has.
int write_species_files(StageContext& ctx, const Forest& f, const std::vector<SpeciesInput>& inputs,
                        const std::vector<std::string>& names) {
  int level_count = 0;
  for (std::size_t s = 0; s < inputs.size(); ++s) {
    const SpeciesInput& in = inputs[s];
    level_count = std::max(level_count, int(f.species[s].levels.size()));
    for (std::size_t l = 0; l < in.levels.size(); ++l) {
      ctx.write_output(f.species[s].levels[l].file, species_level_gltf(in.levels[l]));
      ctx.link_output(in.levels[l].bin_name, *in.level_bins[l]);
    }
    if (in.has_impostor) {
      ctx.write_output(f.species[s].levels.back().file, species_level_gltf(in.impostor.source));
      ctx.write_output(in.impostor.source.bin_name, in.impostor.bin);
      if (in.octahedral) {
        impostor::ImpostorInfo info = in.impostor_info;
        info.glb_file = f.species[s].levels.back().file;  // its cards' glTF here
        ctx.write_output(f.species[s].levels.back().octahedral, impostor::write_impostor_json(info));
        ctx.link_output(in.impostor_info.color_map, *in.color_map);
        ctx.link_output(in.impostor_info.normal_depth_map, *in.normal_depth_map);
      }
    }
    for (const ArtifactFile* im : in.images) ctx.link_output(names[s] + "_" + im->name, *im);
  }
  return level_count;
}

// Tile t's file names: tile_<ix>_<iz>.bin and tile_<ix>_<iz>_lod<l>.gltf.
std::string tile_stem(const Forest& f, std::size_t t) {
  return "tile_" + std::to_string(f.tiles[t].ix) + "_" + std::to_string(f.tiles[t].iz);
}
std::string tile_file(const Forest& f, std::size_t t, int l) {
  return tile_stem(f, t) + "_lod" + std::to_string(l) + ".gltf";
}

// One glTF per tile and level (each species' level l of level_count, species_level), and with
// GPU instancing the tile's one buffer, which all its levels share.
void write_tiles(StageContext& ctx, const Forest& f, const std::vector<SpeciesInput>& inputs, int level_count,
                 TileInstancing instancing) {
  for (std::size_t t = 0; t < f.tiles.size(); ++t) {
    ctx.check_cancelled();
    std::string bin;
    for (int l = 0; l < level_count; ++l) {
      std::vector<const LevelSource*> srcs;
      for (std::size_t s = 0; s < inputs.size(); ++s) {
        const std::size_t sl = species_level(f.species[s], l, level_count);
        srcs.push_back(sl < inputs[s].levels.size() ? &inputs[s].levels[sl] : &inputs[s].impostor.source);
      }
      TileFiles tf;
      try {
        tf = tile_gltf(f, f.tiles[t], srcs, tile_stem(f, t) + ".bin", instancing);
      } catch (const std::invalid_argument& e) {
        throw StageError(e.what());
      }
      ctx.write_output(tile_file(f, t, l), tf.gltf);
      bin = std::move(tf.bin);
    }
    if (instancing == TileInstancing::kGpu) ctx.write_output(tile_stem(f, t) + ".bin", bin);
  }
}

class ForestStage final : public Stage {
 public:
  ForestStage() : info_(forest_stage_info()) {}
  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    // 1. Species: the i-th lod input with species[i].
    const ForestInputs io = check_inputs(ctx);
    const Value::List& species_params = ctx.param("species").as_list();
    LayoutParams lp;
    const std::vector<double> size = reals(ctx.param("size_m"));
    lp.width_m = size[0];
    lp.depth_m = size[1];
    lp.method = ctx.string("method") == "poisson" ? Method::kPoisson : Method::kCelba;
    lp.allow_intersection = ctx.real("allow_intersection");
    lp.retries = int(ctx.integer("retries"));
    std::vector<std::string> names;
    std::vector<SpeciesInput> inputs;
    for (std::size_t i = 0; i < io.lods.size(); ++i) {
      const Value::Object& sp = species_params[i].as_object();
      const std::string& name = sp.at("name").as_string();
      names.push_back(name);
      inputs.push_back(read_species(ctx, *io.lods[i], name));
      if (!io.impostors.empty()) read_impostor(ctx, *io.impostors[i], name, inputs.back());
      inputs.back().parallax = parallax_table(sp.at("impostor_parallax"), name, inputs.back().octahedral);
      lp.species.push_back(species_rule(sp, inputs.back().bounds));
    }

    // 2. Terrain, density map, exclusions, rows, explicit positions.
    read_maps(ctx, lp);
    read_placements(ctx, names, lp);

    // 3. Layout, hierarchy, tiles.
    Rng rng = ctx.rng("layout");
    LayoutResult layout;
    try {
      layout = lay_out(lp, rng, [&] { ctx.check_cancelled(); });
    } catch (const std::invalid_argument& e) {
      throw StageError(e.what());
    }
    Forest f;
    f.extent_min = {-0.5 * lp.width_m, -0.5 * lp.depth_m};
    f.extent_max = {0.5 * lp.width_m, 0.5 * lp.depth_m};
    f.tile_size_m = ctx.real("tile_size_m");
    f.nodes_per_node = int(ctx.integer("nodes_per_node"));
    f.method = ctx.string("method");
    f.seed = std::uint64_t(ctx.integer("seed"));
    f.ground = "ground.glb";
    f.stats = layout.stats;
    for (std::size_t s = 0; s < lp.species.size(); ++s)
      f.species.push_back(forest_species(names[s], inputs[s], lp.species[s]));
    add_instances(f, layout, ctx);
    const auto binary_from = std::size_t(ctx.integer("binary_table_from"));
    f.binary_table = f.instances.size() >= binary_from;

    // 4. Outputs.
    const Box3 ground_bounds = write_ground(ctx, f, lp.terrain);
    const EncodedForest enc = write_instances(f);
    ctx.write_output(kInstancesJson, enc.json);
    if (f.binary_table) ctx.write_output(kInstancesBin, enc.bin);
    const int level_count = write_species_files(ctx, f, inputs, names);
    const TileInstancing instancing =
        ctx.param("tile_instancing").as_string() == "nodes" ? TileInstancing::kNodes : TileInstancing::kGpu;
    write_tiles(ctx, f, inputs, level_count, instancing);
    const Value::Object& geo = ctx.param("georeference").as_object();
    const Georeference g{geo.at("longitude_deg").as_real(), geo.at("latitude_deg").as_real(),
                         geo.at("height_m").as_real()};
    auto tile_name = [&](std::size_t t, int l) { return tile_file(f, t, l); };
    ctx.write_output(kTilesetJson, tileset_json(f, level_count, g, tile_name, ground_bounds));
    const Value::Object& cams = ctx.param("cameras").as_object();
    ForestCameraOptions co;
    co.width_px = int(cams.at("width_px").as_int());
    co.height_px = int(cams.at("height_px").as_int());
    co.frames_per_path = int(cams.at("frames_per_path").as_int());
    co.supersample = int(cams.at("supersample").as_int());
    co.fov_y_deg = f.species.empty() ? 45 : f.species[0].fov_y_deg;
    ctx.write_output(kCameraSetFile, forest_camera_set(f, lp.terrain, co));
  }

 private:
  StageInfo info_;
};

}  // namespace

std::unique_ptr<Stage> make_forest_stage() { return std::make_unique<ForestStage>(); }

}  // namespace sylva
