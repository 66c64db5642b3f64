#include "stages/forest/forest_info.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

namespace sylva {

namespace {
// Bump whenever the bytes of any output can change.
constexpr int kVersion = 9;

ParamSpec optional_path(const std::string& name, const std::string& doc) {
  ParamSpec p = Param::path(name).describe(doc);
  p.default_value = Value(std::string());  // absent = not used (no file enters the key)
  return p;
}
}  // namespace

namespace {

// A species' longest file name, <name>_impostor_normal_depth.png, stays within the engine's 128.
constexpr std::size_t kMaxSpeciesName = 64;

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::vector<double> reals(const Value& v) {
  std::vector<double> out;
  for (const Value& e : v.as_list()) out.push_back(e.as_real());
  return out;
}

}  // namespace

std::vector<ParamProblem> forest_param_problems(const Value::Object& params) {
  std::vector<ParamProblem> out;
  auto problem = [&](std::vector<std::string> path, std::string message) {
    out.push_back({std::move(path), std::move(message)});
  };
  static const std::regex kName("[A-Za-z0-9_-]+");
  std::vector<std::string> names;
  const Value::List& species = params.at("species").as_list();
  for (std::size_t i = 0; i < species.size(); ++i) {
    const Value::Object& sp = species[i].as_object();
    const std::string is = std::to_string(i);
    const std::string& name = sp.at("name").as_string();
    if (name.size() > kMaxSpeciesName)
      problem({"species", is, "name"}, "'" + name.substr(0, kMaxSpeciesName) + "...' is longer than " +
                                           std::to_string(kMaxSpeciesName) + " characters");
    else if (!std::regex_match(name, kName))
      problem({"species", is, "name"}, "'" + name + "' must match [A-Za-z0-9_-]+");
    else if (name.starts_with("tile_"))  // tile_<ix>_<iz>[_lod<L>]: it would overwrite the tile files
      problem({"species", is, "name"}, "'" + name + "' must not begin with 'tile_' (the tile files' names)");
    for (std::size_t j = 0; j < names.size(); ++j)
      if (names[j] == name)
        problem({"species", is, "name"},
                "'" + name + "' is the name of species[" + std::to_string(j) + "] too");
    names.push_back(name);
    for (const char* key : {"scale_x", "scale_y", "scale_z"}) {
      const std::vector<double> r = reals(sp.at(key));
      if (r[0] > r[1])
        problem({"species", is, key},
                "must be [min, max] with min <= max, got [" + number(r[0]) + ", " + number(r[1]) + "]");
    }
    if (sp.at("min_altitude_m").as_real() > sp.at("max_altitude_m").as_real())
      problem({"species", is, "max_altitude_m"}, "must be at least min_altitude_m (" +
                                                     number(sp.at("min_altitude_m").as_real()) + "), got " +
                                                     number(sp.at("max_altitude_m").as_real()));
    const std::vector<double> px = reals(sp.at("impostor_parallax"));
    if (px.size() % 2) {
      problem({"species", is, "impostor_parallax"},
              "must be pairs [from_m, steps, ...], got " + std::to_string(px.size()) + " numbers");
    } else {
      for (std::size_t k = 0; k < px.size(); k += 2) {
        if (!(px[k + 1] >= 0 && px[k + 1] <= 64 && px[k + 1] == std::floor(px[k + 1])))
          problem({"species", is, "impostor_parallax"},
                  "steps must be integers 0..64, got " + number(px[k + 1]));
        if (k > 0 && !(px[k] > px[k - 2]))
          problem({"species", is, "impostor_parallax"},
                  "distances must increase, got " + number(px[k]) + " after " + number(px[k - 2]));
      }
    }
  }
  auto pairs = [&](const std::string& list, std::size_t j, const Value::Object& item) {
    const std::size_t n = item.at("points").as_list().size();
    if (n % 2)
      problem({list, std::to_string(j), "points"},
              "must be x, z pairs (an even count), got " + std::to_string(n) + " numbers");
  };
  const Value::List& exclusions = params.at("exclusions").as_list();
  for (std::size_t j = 0; j < exclusions.size(); ++j) pairs("exclusions", j, exclusions[j].as_object());
  const Value::List& rows = params.at("rows").as_list();
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const Value::Object& row = rows[j].as_object();
    pairs("rows", j, row);
    const std::string& sp = row.at("species").as_string();
    if (std::find(names.begin(), names.end(), sp) == names.end())
      problem({"rows", std::to_string(j), "species"}, "'" + sp + "' is not in 'species'");
  }
  const std::vector<double> te = reals(params.at("terrain_extent_m"));
  if (!te.empty() && (te.size() != 4 || !(te[2] > te[0]) || !(te[3] > te[1])))
    problem({"terrain_extent_m"}, "must be [x0, z0, x1, z1] with x1 > x0 and z1 > z0");
  else if (!te.empty() && params.at("height_map").as_string().empty())
    problem({"terrain_extent_m"}, "places the height map, but there is no height_map");
  return out;
}

std::vector<ParamProblem> forest_input_problems(const Value::Object& params,
                                                const std::vector<std::string>& input_types) {
  const std::size_t species = params.at("species").as_list().size();
  const auto lods = std::size_t(std::count(input_types.begin(), input_types.end(), "lod"));
  if (species == lods) return {};
  return {{{"species"},
           "lists " + std::to_string(species) + " entries but the node needs " + std::to_string(lods) +
               " lod inputs (one entry per lod input, in the order of 'needs')"}};
}

namespace {

// The layout's parameters: seed, area and Celba's placement method.
std::vector<ParamSpec> layout_params() {
  return {
      Param::integer("seed", 1)
          .range(0, 4294967295.0)
          .describe("random seed: same recipe -> byte-identical forest"),
      Param::real_list("size_m", Value::List{100.0, 100.0})
          .items(2, 2)
          .range(1, 1e6)
          .describe("Celba's Width x Depth (x, z), metres; the area is centred on the origin"),
      Param::choice("method", {"celba", "poisson"}, "celba")
          .describe(
              "celba: Alg. 8 (random positions, box overlap test); poisson: variable-radius Poisson disk"),
      Param::real("allow_intersection", 0.1)
          .range(0, 1)
          .describe("Celba's AllowIntersection: reject when the overlap with any one placed box exceeds this "
                    "x own volume"),
      Param::integer("retries", 10)
          .range(0, 10000)
          .describe("Celba's NumberOfRetries (poisson: candidates per active sample, Bridson's k)"),
  };
}

// How the forest is grouped for streaming: the hierarchy and the tiles.
std::vector<ParamSpec> tiling_params() {
  return {
      Param::integer("nodes_per_node", 64)
          .range(2, 100000)
          .describe("Celba's NodesPerNode: children per hierarchy node"),
      Param::real("tile_size_m", 50)
          .range(1, 1e6)
          .describe("square streaming tiles (glTF per tile and level, 3D Tiles)"),
      Param::choice("tile_instancing", {"gpu", "nodes"}, "gpu")
          .describe("gpu: a tile draws each species' triangles with EXT_mesh_gpu_instancing (required), its "
                    "lines with one node per tree; nodes: one plain node per tree, no extension (for clients "
                    "without it: Blender, Godot, Unreal)"),
  };
}

// `species`: one entry per lod input, Celba's per-type parameters and the Poisson spacing.
ParamSpec species_param() {
  return Param::object_list(
      "species",
      {Param::string("name").describe("species name ([A-Za-z0-9_-]+), in instances.json and file names"),
       Param::real("density_per_ha", 10).range(0, 1e6).describe("Celba's Density: trees per 10 000 m^2"),
       Param::real_list("scale_x", Value::List{1.0, 1.0})
           .items(2, 2)
           .range(1e-3, 1e3)
           .describe("Celba's SizeDeviationXMin/Max"),
       Param::real_list("scale_y", Value::List{1.0, 1.0})
           .items(2, 2)
           .range(1e-3, 1e3)
           .describe("Celba's SizeDeviationYMin/Max (height)"),
       Param::real_list("scale_z", Value::List{1.0, 1.0})
           .items(2, 2)
           .range(1e-3, 1e3)
           .describe("Celba's SizeDeviationZMin/Max"),
       Param::real_list("base_rotation_deg", Value::List{0.0, 0.0, 0.0})
           .items(3, 3)
           .range(-360, 360)
           .describe("Celba's BaseRotationX/Y/Z (applied X, then Y, then Z)"),
       Param::real("base_translation_y_m", 0).range(-1e4, 1e4).describe("Celba's BaseTranslationY"),
       Param::boolean("random_yaw", true).describe("yaw uniform in [0, 360) deg (Celba §4.5.4)"),
       Param::real("max_slope_deg", 90).range(0, 90).describe("terrain: no tree where the ground is steeper"),
       Param::real("min_altitude_m", -1e9).range(-1e9, 1e9).describe("terrain: lowest ground height"),
       Param::real("max_altitude_m", 1e9).range(-1e9, 1e9).describe("terrain: highest ground height"),
       Param::real("min_spacing_m", 0)
           .range(0, 1e4)
           .describe("poisson: minimum distance to any tree (0 = half the footprint's diagonal)"),
       Param::real_list("impostor_parallax", Value::List{})
           .range(0, 1e9)
           .describe("pairs [from_m, steps, ...]: from from_m on (impostor.json's terms) forest views draw "
                     "the octahedral impostor with `steps` parallax steps instead of 16 (0 = flat), each "
                     "distance proven by `sylva impostorcheck --parallax-steps N --search-distance`")});
}

// Where trees may stand and where the user puts them: terrain, density map, exclusions, rows,
// explicit positions.
std::vector<ParamSpec> placement_params() {
  return {
      optional_path("height_map", "terrain height map (16-bit PNG, EXR, ...; grey 0..1 -> height_range_m)"),
      Param::real_list("height_range_m", Value::List{0.0, 10.0})
          .items(2, 2)
          .range(-1e4, 1e5)
          .describe("terrain heights of grey 0 and 1, metres"),
      Param::real_list("terrain_extent_m", Value::List{})
          .items(0, 4)
          .range(-1e7, 1e7)
          .describe("[x0, z0, x1, z1] the height map covers (default: the forest area)"),
      optional_path("density_map", "image multiplying every density (grey 0..1 over the forest area)"),
      Param::object_list("exclusions",
                         {Param::real_list("points")
                              .items(6, std::nullopt)
                              .range(-1e7, 1e7)
                              .describe("polygon x0, z0, x1, z1, ... (>= 3 points): glade, road")}),
      Param::object_list(
          "rows",
          {Param::string("species").describe("species name"),
           Param::real_list("points")
               .items(4, std::nullopt)
               .range(-1e7, 1e7)
               .describe("polyline x0, z0, x1, z1, ... (>= 2 points)"),
           Param::real("spacing_m", 5).range(0.01, 1e5).describe("distance between trees along the line"),
           Param::real("jitter_m", 0)
               .range(0, 1e4)
               .describe("each tree moved uniformly within this radius")}),
      optional_path("positions", "CSV of explicit trees: species,x,z[,yaw_deg][,scale]"),
  };
}

// The outputs' options: the instance table's form, the tileset's georeference, the cameras.
std::vector<ParamSpec> output_params() {
  return {
      Param::integer("binary_table_from", 100000)
          .range(0, 4294967295.0)
          .describe("instances go to instances.bin from this many trees on (0 = always)"),
      Param::object("georeference", {Param::real("longitude_deg", 0).range(-180, 180),
                                     Param::real("latitude_deg", 45).range(-90, 90),
                                     Param::real("height_m", 0).range(-1e4, 1e5)}),
      Param::object(
          "cameras",
          {Param::integer("width_px", 960).range(16, 8192), Param::integer("height_px", 540).range(16, 8192),
           Param::integer("frames_per_path", 2).range(1, 100),
           Param::integer("supersample", 2)
               .range(1, 2)
               .describe("2: meshes drawn 2 x 2 supersampled, impostors with 4x MSAA "
                         "(4 samples per pixel either way); 1: everything with 4x MSAA")}),
  };
}

// Every parameter, in the order the CLI lists them (docs/stages/forest.md explains each).
std::vector<ParamSpec> forest_params() {
  std::vector<ParamSpec> params = layout_params();
  auto append = [&](std::vector<ParamSpec> group) {
    params.insert(params.end(), group.begin(), group.end());
  };
  append(tiling_params());
  params.push_back(species_param());
  append(placement_params());
  append(output_params());
  return params;
}

}  // namespace

StageInfo forest_stage_info() {
  StageInfo info;
  info.name = "forest";
  info.version = kVersion;
  info.summary =
      "Celba Alg. 8 forest layout (+ yaw, terrain, density map, exclusions, rows, CSV, Poisson), "
      "instanced glTF tiles per LOD level, 3D Tiles tileset, forest cameras";
  info.inputs = InputSpec{{"lod", "impostor"},
                          1,
                          -1,
                          "species: the i-th lod input is species[i] (with the i-th impostor input, if any)"};
  info.output_type = "forest";
  info.check = forest_param_problems;
  info.check_inputs = forest_input_problems;
  info.params = forest_params();
  return info;
}

}  // namespace sylva
