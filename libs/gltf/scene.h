// The glTF scene every sylva stage writes: plain data that libs/gltf/writer.h turns into a GLB or
// .gltf file (glTF 2.0 core; KHR_draco_mesh_compression, KHR_materials_unlit and
// EXT_mesh_gpu_instancing when used). Only what the pipeline needs is modelled; docs/gltf.md says
// exactly what is emitted.
//
// Contract (validate_scene() checks every point and encode_* refuses a scene that breaks one, so
// every file written passes the Khronos glTF-Validator with zero errors):
//   - Units and frames are glTF's: metres, Y up, right-handed, counter-clockwise front faces.
//   - A Primitive's attributes are flat float arrays, one entry per vertex: positions xyz
//     (required, finite, at least one vertex), normals xyz (unit length within 1e-4), tangents
//     xyzw (xyz unit within 1e-4, w exactly +1 or -1; only together with normals), texcoords uv
//     (glTF convention: origin at the image's top-left), colors rgba (linear, in [0, 1]); an
//     empty vector means "absent". Custom attributes (names starting with '_', e.g. "_SIZE") have
//     1..4 components.
//   - indices (optional) index the vertices; their count fits the mode (triangles: multiple of
//     3, lines: multiple of 2). Without indices the vertex count must fit the mode instead.
//   - Indices into materials, images, meshes and nodes are in range; -1 means none. The node
//     graph is a forest; `roots` lists the scene's root nodes, each at most once.
//   - extras and Node::extensions are JSON objects (or null = none) and are written as they are.
//   - Written but not stored: materials no primitive uses, images no written material uses, and
//     tangents of primitives whose material has no normal map (docs/gltf.md).
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace sylva::gltf {

enum class PrimitiveMode : int { kPoints = 0, kLines = 1, kTriangles = 4 };

enum class AlphaMode { kOpaque, kMask, kBlend };

enum class Wrap : int { kRepeat = 10497, kClampToEdge = 33071, kMirroredRepeat = 33648 };

// An encoded image file (PNG or JPEG), embedded byte for byte: the writer never re-encodes.
struct Image {
  std::string name;                     // e.g. "bark.png"; informative only
  std::string mime_type = "image/png";  // "image/png" or "image/jpeg"
  std::string bytes;                    // the file's bytes, non-empty
  // FileFormat::kGltfExternal only: the image is a file of this name beside the .gltf (a plain
  // file name: letters, digits, '.', '_', '-'). Empty: embedded in buffer 0 as in the other formats.
  std::string uri;
};

// A texture use: an image with its sampler's wrap modes. Filtering is always linear with
// mipmaps (LINEAR_MIPMAP_LINEAR / LINEAR). The writer shares equal samplers and textures.
struct TextureRef {
  int image = -1;  // index into Scene::images, -1 = no texture
  Wrap wrap_s = Wrap::kRepeat;
  Wrap wrap_t = Wrap::kRepeat;
};

// pbrMetallicRoughness with a base colour; the textures are read with TEXCOORD_0.
struct Material {
  std::string name;
  std::array<float, 4> base_color{1, 1, 1, 1};  // linear RGBA factor, each in [0, 1]
  TextureRef base_color_texture;
  TextureRef normal_texture;  // tangent-space normal map (normalTexture); TANGENT is written only with one
  float metallic = 0;         // [0, 1]
  float roughness = 1;        // [0, 1]
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;  // used with kMask only, >= 0
  bool double_sided = false;
  bool unlit = false;  // KHR_materials_unlit
  nlohmann::json extras;
};

// A vertex attribute outside the glTF core names, written as FLOAT SCALAR/VEC2/VEC3/VEC4.
struct CustomAttribute {
  std::string name;  // must start with '_' (glTF rule for application-specific semantics)
  int components = 1;
  std::vector<float> values;  // components per vertex
};

struct Primitive {
  PrimitiveMode mode = PrimitiveMode::kTriangles;
  std::vector<float> positions;         // xyz per vertex (required)
  std::vector<float> normals;           // xyz per vertex or empty
  std::vector<float> tangents;          // xyzw per vertex or empty
  std::vector<float> texcoords;         // uv per vertex or empty (TEXCOORD_0)
  std::vector<float> colors;            // rgba per vertex or empty (COLOR_0)
  std::vector<CustomAttribute> custom;  // written in name order
  std::vector<std::uint32_t> indices;   // empty = non-indexed
  int material = -1;                    // index into Scene::materials or -1 (glTF default material)
  nlohmann::json extras;
  int buffer = -1;  // kGltfExternal only: index into Scene::buffer_uris; -1 = the mesh's buffer

  std::size_t vertex_count() const { return positions.size() / 3; }
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;  // at least one
  nlohmann::json extras;
  // FileFormat::kGltfExternal only: index into Scene::buffer_uris, the .bin file that holds this
  // mesh's data (and its nodes' instancing attributes). Ignored by GLB and embedded .gltf.
  int buffer = 0;
};

// EXT_mesh_gpu_instancing: the node's mesh drawn once per instance, each placed by its own
// translation / rotation (unit quaternion xyzw) / scale in the node's local space. Arrays are
// either empty (identity) or hold one entry per instance; at least one must be non-empty.
struct Instances {
  std::vector<float> translations;  // xyz per instance
  std::vector<float> rotations;     // xyzw per instance
  std::vector<float> scales;        // xyz per instance
  bool empty() const { return translations.empty() && rotations.empty() && scales.empty(); }
};

struct Node {
  std::string name;
  int mesh = -1;              // index into Scene::meshes or -1
  std::vector<int> children;  // node indices
  std::array<double, 3> translation{0, 0, 0};
  std::array<double, 4> rotation{0, 0, 0, 1};  // unit quaternion xyzw
  std::array<double, 3> scale{1, 1, 1};
  Instances instances;  // requires mesh >= 0 when not empty
  // Further node extensions, written as they are: a JSON object {name: value}, e.g.
  // {"MSFT_lod": {"ids": [3, 4]}}; each name goes into extensionsUsed (and extensionsRequired
  // when listed in Scene::extensions_required). Null = none. (Instancing has its own field.)
  nlohmann::json extensions;
  nlohmann::json extras;
};

struct Scene {
  std::vector<Node> nodes;
  std::vector<int> roots;  // root nodes of the (single, default) scene
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Image> images;
  std::string generator = "sylva";               // asset.generator; no version or date, so bytes stay stable
  nlohmann::json extras;                         // written as asset.extras (sylva metadata, docs/gltf.md)
  std::vector<std::string> extensions_required;  // names of Node::extensions a reader must know
  // FileFormat::kGltfExternal only: the file name of each buffer (plain names as Image::uri).
  // Buffer b holds, in mesh and primitive order, the data of every primitive assigned to b
  // (Primitive::buffer, else its Mesh::buffer), laid out exactly as in a scene that holds those
  // primitives alone: so two .gltf files can share one .bin, or one a prefix of the other's.
  std::vector<std::string> buffer_uris;
  // kGltfExternal only, optional: the byteLength to declare for buffer b when the file of that
  // name is longer than this scene's data for it (another scene wrote it, with this scene's data
  // as its prefix). 0 or absent = the data's own length; smaller than the data is an error.
  std::vector<std::size_t> buffer_byte_lengths;
};

// Every broken contract point, one message each ("meshes[0].primitives[1]: normals has 5
// values, expected 3 per vertex (12)"); empty when the scene can be written. Stops after
// `max_errors` messages.
std::vector<std::string> validate_scene(const Scene& scene, std::size_t max_errors = 20);

}  // namespace sylva::gltf
