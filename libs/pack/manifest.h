// pack/manifest.json (issue 14; docs/stages/pack.md "manifest.json"): the one
// reader and writer of an asset pack's table of contents, used by stage `pack` and by
// `sylva pack diff`.
//
// The manifest lists every other file of the pack with its SHA-256, size, media type and what
// produced it (the stage, its version, and the digests of the input files it was made from),
// then each species' chain of files, and the pack's total size. Bytes are canonical: object keys
// sorted, files sorted by path, species sorted by name, two-space indent, a final newline; so the
// same pack gives the same manifest bytes on every run.
//
// Upstream node names are not recorded: they are not part of a node's action key (renaming a
// node does not rebuild the pack), so a manifest naming them could name them wrongly. What ties a
// file to its inputs is the input digests, which are part of the key.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "libs/pack/lod_json.h"

namespace sylva::pack {

// Writes version 4; reads 1 (no forests, level file names only), 2 (level file names only), 3
// (levels without `measured`) and 4 (levels may carry `measured`).
inline constexpr int kManifestVersion = 4;
inline constexpr const char* kManifestFile = "manifest.json";  // the file's name in a pack

// A manifest that cannot be read: what() names the file and the JSON element.
class ManifestError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Producer {
  std::string stage;      // e.g. "pack"
  int stage_version = 0;  // the stage's implementation version
  // The input files this file was made from: "<input artifact type>/<file name>" -> hex SHA-256.
  std::map<std::string, std::string> inputs;
  friend bool operator==(const Producer&, const Producer&) = default;
};

struct FileEntry {
  std::string path;        // relative to the manifest's directory, '/'-separated, e.g. "oak.glb"
  std::string sha256;      // 64 lowercase hex digits
  std::uint64_t size = 0;  // bytes
  std::string media_type;  // e.g. "model/gltf-binary"
  Producer producer;
  friend bool operator==(const FileEntry&, const FileEntry&) = default;
};

// One species' chain in the pack.
struct SpeciesEntry {
  std::string name;      // e.g. "oak"
  std::string chain;     // the MSFT_lod file, e.g. "oak.glb"
  std::string lod_json;  // e.g. "oak.lod.json"
  // One entry per level, nearest first: its file ("oak_lod0.glb", ...) and, from version 3, its
  // numbers as lod.json states them (epsilon, delta, switch distance, screen coverage,
  // primitives, bytes, position grid; libs/pack/lod_json.h). A version 1 or 2 manifest gives
  // the file only (every number 0, kind "mesh").
  std::vector<LodLevel> levels;
  // the impostor level's file (also the last of `levels`), empty when the chain has none
  std::string impostor;
  friend bool operator==(const SpeciesEntry&, const SpeciesEntry&) = default;
};

// One forest in the pack (a `forest` artifact's files, copied under their own names: its glTF
// tiles name the species' level files and .bin buffers by those names).
struct ForestEntry {
  std::string name;                // e.g. "forest"
  std::string tileset;             // the 3D Tiles tileset, e.g. "tileset.json"
  std::string instances;           // instances.json
  std::vector<std::string> tiles;  // the tile glTF files (tile_<ix>_<iz>_lod<L>.gltf), sorted
  std::vector<std::string> files;  // every file of the forest (tiles and tileset included), sorted
  friend bool operator==(const ForestEntry&, const ForestEntry&) = default;
};

struct Manifest {
  int version = kManifestVersion;     // as read; write_manifest always writes kManifestVersion
  std::vector<FileEntry> files;       // sorted by path on write
  std::vector<SpeciesEntry> species;  // sorted by name on write
  std::vector<ForestEntry> forests;   // sorted by name on write
  std::uint64_t total_bytes() const;  // sum of the files' sizes (written, checked on read)
  const FileEntry* file(std::string_view path) const;
  friend bool operator==(const Manifest&, const Manifest&) = default;
};

// The entry for `bytes` stored as `path` (SHA-256 and size computed, media type from the name).
FileEntry describe_file(std::string path, std::string_view bytes, Producer producer);

// "model/gltf-binary" (.glb), "model/gltf+json" (.gltf), "application/json" (.json),
// "image/png", "image/ktx2", "application/yaml" (.yaml), "application/octet-stream" (.bin and
// anything else).
std::string media_type_for(std::string_view path);

// Canonical bytes (header comment). Throws ManifestError when two files share a path, or a
// species or forest names a file the manifest does not list.
std::string write_manifest(const Manifest& manifest);

// Parses manifest bytes; `source` names them in messages ("out/x/pack/manifest.json"). Checks the
// version, every field's type, the digests' form and total_bytes. Throws ManifestError.
Manifest parse_manifest(std::string_view text, const std::string& source);
Manifest read_manifest(const std::filesystem::path& path);

// What changed between two packs: paths only in `new_manifest` (added), in both with another
// SHA-256 (changed), only in `old_manifest` (removed); each list sorted.
struct ManifestDiff {
  std::vector<std::string> added, changed, removed;
  bool empty() const { return added.empty() && changed.empty() && removed.empty(); }
};
ManifestDiff diff_manifests(const Manifest& old_manifest, const Manifest& new_manifest);

}  // namespace sylva::pack
