// The geometry of an imported tree mesh, kept as the user's file had it: triangles, materials
// and images, after the import's unit and axis conversion (metres, Y up) and recentring. An
// imported tree's LOD level 0 is this geometry; the skeleton and leaves that the hierarchy stage
// reconstructs from it drive the coarser levels (docs/stages/hierarchy.md). Generated and QSM
// trees have none (SourceGeometry::empty()).
//
// Invariants (validate_source_geometry() checks them; the .sylt writer refuses to break them and
// the reader enforces them):
//   - every primitive: indices.size() a multiple of 3, every index < positions.size();
//     normals and uvs empty or one per position; positions, normals, uvs finite; normals unit
//     length within 1e-3; material < materials.size();
//   - every material: base_color components in [0, 1]; alpha_cutoff in [0, 1];
//     base_color_image -1 or < images.size();
//   - every image: mime_type "image/png" or "image/jpeg" and non-empty bytes;
//   - names at most kMaxTextBytes (tree.h) bytes; at most kMaxSourceVertices vertices and
//     kMaxSourceTriangles triangles over all primitives.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "libs/tree/vec3.h"

namespace sylva::tree {

// glTF 2.0 alphaMode: opaque, alpha-tested at alpha_cutoff, or blended.
enum class AlphaMode : std::uint8_t { kOpaque = 0, kMask = 1, kBlend = 2 };

// An image the file embedded or referenced, stored whole (encoded PNG or JPEG bytes).
struct SourceImage {
  std::string name;       // the file's name for it (URI, or "<mesh>.image<i>" when embedded)
  std::string mime_type;  // "image/png" or "image/jpeg"
  std::string bytes;      // the encoded image
  friend bool operator==(const SourceImage&, const SourceImage&) = default;
};

// A metallic-roughness material reduced to what a tree needs (glTF 2.0 pbrMetallicRoughness).
struct SourceMaterial {
  std::string name;
  std::array<float, 4> base_color{1, 1, 1, 1};  // linear RGBA, each in [0, 1]
  std::int32_t base_color_image = -1;           // index into SourceGeometry::images, -1 = none
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;  // [0, 1], used by kMask
  bool double_sided = false;
  float metallic = 0;   // [0, 1]
  float roughness = 1;  // [0, 1]
  friend bool operator==(const SourceMaterial&, const SourceMaterial&) = default;
};

// One triangle list with one material. `name` is the node path the importer found it under
// ("<node>/<child>/<mesh>"): Celba's naming rules (br<level>*, lf*) read its last component.
struct SourcePrimitive {
  std::string name;
  std::uint32_t material = 0;
  std::vector<Vec3f> positions;           // m, tree space
  std::vector<Vec3f> normals;             // empty or one unit vector per position
  std::vector<std::array<float, 2>> uvs;  // empty or one per position; texture transform applied
  std::vector<std::uint32_t> indices;     // triangle list, counter-clockwise front faces
  friend bool operator==(const SourcePrimitive&, const SourcePrimitive&) = default;
};

inline constexpr std::size_t kMaxSourceVertices = std::size_t(1) << 24;   // 16.7 M
inline constexpr std::size_t kMaxSourceTriangles = std::size_t(1) << 24;  // 16.7 M

struct SourceGeometry {
  std::vector<SourcePrimitive> primitives;
  std::vector<SourceMaterial> materials;
  std::vector<SourceImage> images;
  bool empty() const { return primitives.empty(); }
  friend bool operator==(const SourceGeometry&, const SourceGeometry&) = default;
};

// Every broken invariant (above), one message per problem naming the element
// ("source primitive 3 (\"lf_12\"): index 9 at triangle 2 is not below 8 positions"). Empty when
// valid. Stops after `max_errors` messages.
std::vector<std::string> validate_source_geometry(const SourceGeometry& g, std::size_t max_errors = 20);

}  // namespace sylva::tree
