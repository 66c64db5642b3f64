// instances.json (+ instances.bin): what a `forest` artifact is, for every program that reads one
// (the forest stage writes it; `sylva render`, the verify stage, `sylva lodcheck` and engines
// read it). The one reader and writer of the format (docs/formats.md, docs/stages/forest.md).
//
// A forest is a list of species (each with its LOD levels and optional impostor, the files of
// this artifact that draw them) and a list of tree instances placed in the forest's frame:
// metres, Y up, right-handed (glTF's), the forest's area centred on the origin. Instance i's
// world matrix is
//     W = T(position) * R_y(yaw) * S(scale) * B_species,
//     B_species = T_y(base_translation_y) * R_z(rz) * R_y(ry) * R_x(rx)   (Celba §4.5.3's order:
//     rotate about X, then Y, then Z, then translate along Y),
// applied to the species' asset (its level meshes, in their own object space).
//
// Contract: write_instances(forest) gives deterministic bytes (fixed key order; reals in
// shortest round-trip form); read_instances(write_instances(f)) == f, bit for bit, for inline
// and binary tables alike. The binary table (instances.bin, when Forest::binary_table is set)
// holds the instances as little-endian records of kRecordBytes (layout in docs/stages/forest.md
// "instances.json"), instances.json then carries everything else. parse_* check every field's presence, type
// and range and throw FormatError("<source>: error: <what>") on the first problem; never crash.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/fileio/file_source.h"

namespace sylva::forest {

class FormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using Vec3d = std::array<double, 3>;

struct Box3 {
  Vec3d min{0, 0, 0}, max{0, 0, 0};
  friend bool operator==(const Box3&, const Box3&) = default;
};

// One level of a species' chain as the forest draws it: a glTF file of this artifact (the
// species' level mesh alone, in object space) with the level's spatial error and switch distance
// (docs/lod-model.md: valid from switch_distance_m on, at the chain's camera and delta).
// A row of an octahedral impostor level's parallax table: from `from_m` on (a distance in the
// terms of the level's switch distance), the reference impostor shader marches `steps` steps
// (u_parallax_steps; 0 = flat frames) instead of its 16; each row is a distance at which
// `sylva impostorcheck --parallax-steps N` proved the impostor with N steps (docs/stages/forest.md,
// "Impostor parallax").
struct ParallaxStep {
  double from_m = 0;
  int steps = 16;
  friend bool operator==(const ParallaxStep&, const ParallaxStep&) = default;
};

struct Level {
  std::string file;              // e.g. "oak_lod3.gltf"
  double epsilon_m = 0;          // spatial error of the level
  double switch_distance_m = 0;  // d = epsilon / (delta s(1)); level 0's is where it starts
  std::size_t primitives = 0;    // triangles + lines + points of the level mesh
  bool impostor = false;         // the impostor level (the species' last, when it has one)
  // A (hemi-)octahedral impostor: its impostor.json in this artifact (maps beside it), which a
  // renderer with the reference shader draws instead of `file` (the impostor's fallback cards,
  // for plain glTF clients). Empty for billboards, whose cards are the impostor. Written only
  // when set.
  std::string octahedral;
  // Octahedral impostor levels only: the parallax table, from_m strictly increasing, steps in
  // 0..64 (nearer than the first row: 16). Written only when not empty.
  std::vector<ParallaxStep> parallax;
  friend bool operator==(const Level&, const Level&) = default;
};

struct Species {
  std::string name;                  // [A-Za-z0-9_-]+, unique in the forest
  std::string source;                // what it was made from (lod.json's "tree"), informative
  Box3 bounds;                       // the asset's object-space box (level 0)
  Vec3d base_rotation_deg{0, 0, 0};  // rx, ry, rz (Celba's BaseRotationX/Y/Z)
  double base_translation_y_m = 0;   // Celba's BaseTranslationY
  double pixel_error_px = 0.5;       // delta of the chain the switch distances are for
  double fov_y_deg = 45;             // the chain's camera: phi ...
  int height_px = 1080;              // ... and H
  std::vector<Level> levels;         // finest first; the impostor (if any) last
  friend bool operator==(const Species&, const Species&) = default;
};

struct Instance {
  std::uint32_t id = 0;       // stable: the order of placement (docs/stages/forest.md "instances.json")
  std::uint32_t species = 0;  // index into Forest::species
  std::uint32_t tile = 0;     // index into Forest::tiles
  Vec3d position{0, 0, 0};    // metres: the tree's base point on the ground
  double yaw_rad = 0;         // about +Y
  Vec3d scale{1, 1, 1};       // per axis, forest axes (Celba's SizeDeviationX/Y/Z)
  friend bool operator==(const Instance&, const Instance&) = default;
};

// A square streaming tile (tile_size_m): trees whose position falls in [x0, x0 + size) x
// [z0, z0 + size). bounds covers the trees' world boxes (not the square).
struct Tile {
  int ix = 0, iz = 0;  // grid coordinates; x0 = extent_min.x + ix * size
  Box3 bounds;
  std::vector<std::uint32_t> instances;  // indices into Forest::instances, ascending
  friend bool operator==(const Tile&, const Tile&) = default;
};

// Celba §4.5.3's spatial hierarchy: instance nodes grouped by a quadtree into nodes of at most
// nodes_per_node children, repeated until one root. Node 0 is the root; children are node
// indices (inner nodes) or instance indices (leaf nodes, leaf == true).
struct HierarchyNode {
  Box3 bounds;
  bool leaf = false;
  std::vector<std::uint32_t> children;
  friend bool operator==(const HierarchyNode&, const HierarchyNode&) = default;
};

struct SpeciesStats {
  std::size_t requested = 0;  // Celba's expected number: density x allowed area
  std::size_t placed = 0;
  std::size_t dropped = 0;  // gave up after `retries` rejections
  friend bool operator==(const SpeciesStats&, const SpeciesStats&) = default;
};

struct Forest {
  std::array<double, 2> extent_min{0, 0}, extent_max{0, 0};  // x, z of the area
  double tile_size_m = 0;
  int nodes_per_node = 64;
  std::string method;  // "celba" or "poisson"
  std::uint64_t seed = 0;
  // The ground mesh of the forest's area (a GLB of this artifact, object space = the forest's
  // frame; docs/stages/forest.md "Ground"), drawn under the trees. Empty = none; written only when set.
  std::string ground;
  std::vector<Species> species;
  std::vector<SpeciesStats> stats;  // per species
  std::vector<Instance> instances;  // by id: instances[i].id == i
  std::vector<Tile> tiles;          // non-empty tiles, by (iz, ix)
  std::vector<HierarchyNode> hierarchy;
  bool binary_table = false;  // instances in instances.bin rather than inline
  friend bool operator==(const Forest&, const Forest&) = default;
};

// The forest artifact's files that other programs look for by name (docs/stages/forest.md).
inline constexpr const char* kInstancesJson = "instances.json";
inline constexpr const char* kInstancesBin = "instances.bin";
inline constexpr const char* kTilesetJson = "tileset.json";  // the 3D Tiles 1.1 tileset
inline constexpr const char* kCameraSetFile =
    "cameras.yaml";  // the forest's camera set (libs/render/camera.h)
// id u32, species u32, tile u32, position 3 x f64, yaw f64, scale 3 x f64 (little-endian).
inline constexpr std::size_t kRecordBytes = 3 * 4 + 7 * 8;

struct EncodedForest {
  std::string json;
  std::string bin;  // empty unless forest.binary_table
};

EncodedForest write_instances(const Forest& forest);
// `bin` is read only when the JSON says the table is binary (it must then be exactly the table).
Forest parse_instances(const std::string& json, const std::string& bin, const std::string& source_name);
// Reads `json_path` and, when needed, instances.bin beside it, from `files` (the disk, or a
// stage's declared inputs). Throws FormatError "<path>: error: <reason>" if either cannot be read.
Forest read_instances(const std::filesystem::path& json_path,
                      const fileio::FileSource& files = fileio::disk_files());

// W for instance `inst` of `species` (column-major 4x4, acts on column vectors).
std::array<double, 16> instance_matrix(const Species& species, const Instance& inst);
// B_species alone.
std::array<double, 16> base_matrix(const Species& species);
// The axis-aligned box of `box` transformed by the column-major matrix m.
Box3 transform_box(const std::array<double, 16>& m, const Box3& box);

}  // namespace sylva::forest
