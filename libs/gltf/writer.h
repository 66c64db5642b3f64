// Writing a gltf::Scene (scene.h) as GLB or .gltf through tinygltf, optionally with Draco.
//
// Guarantees (docs/gltf.md lists the emitted JSON in detail):
//   - Deterministic: the bytes depend only on the Scene and the options (no time stamps, no
//     pointers, no hash-map order); the same input gives the same file on every run and thread.
//   - Valid: the scene is checked with validate_scene() first; what is written passes the Khronos
//     glTF-Validator with zero errors.
//   - Self-contained: GLB holds everything in its binary chunk; a .gltf carries its one buffer as
//     a base64 data URI (images live in that buffer too), so every output is a single file.
//     Except kGltfExternal (encode_external): JSON plus one .bin per Scene::buffer_uris entry and
//     one file per image with a uri, so several .gltf files can share geometry and textures.
//   - Lean: materials no primitive uses and images no written material uses are left out;
//     TANGENT is written only when the primitive's material has a normal map.
//   - Layout: one buffer; per mesh, per primitive: POSITION, NORMAL, TANGENT, TEXCOORD_0,
//     COLOR_0, custom attributes (name order), indices, each in its own 4-byte aligned buffer
//     view; then the images in order. Indices are UNSIGNED_SHORT when every vertex index fits
//     (vertex count <= 65535), else UNSIGNED_INT. POSITION accessors carry min/max.
//   - Draco (KHR_draco_mesh_compression, listed as required): applies to TRIANGLES primitives
//     only (the extension defines no other modes); LINES and POINTS primitives of the same file
//     stay uncompressed. Positions, normals, uvs, colors and custom attributes are quantised with
//     the bits given; tangents are encoded as a generic attribute. Accessors of a compressed
//     primitive have no buffer view and count what the Draco decoder will return.
//   - meshopt (EXT_meshopt_compression, required): every vertex attribute and index buffer view
//     compressed with meshoptimizer's lossless codecs into the binary chunk, the views in a
//     fallback buffer without data; images stay uncompressed. Values decode bit for bit (with
//     quantisation: to the quantised values; octahedral normals through the OCTAHEDRAL filter).
//   - Quantisation (QuantizeOptions, KHR_mesh_quantization): integer attributes, each in its own
//     view with a byteStride that is a multiple of 4; POSITION min/max are the integer bounds.
#pragma once

#include <filesystem>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "libs/gltf/scene.h"

namespace sylva::gltf {

// The scene breaks its contract (message lists validate_scene()'s findings), Draco failed, or a
// file could not be written. what() is one line.
class GltfError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class FileFormat { kGlb, kGltf, kGltfExternal };

struct DracoOptions {
  bool enabled = false;
  int position_bits = 14;     // 1..30; max position error = extent / (2^bits - 1) / 2 per axis
  int normal_bits = 10;       // 1..30 (octahedral)
  int texcoord_bits = 12;     // 1..30
  int color_bits = 10;        // 1..30
  int generic_bits = 12;      // 1..30: tangents and custom attributes
  int compression_level = 7;  // 0 (fastest) .. 10 (smallest); Draco speed = 10 - level
};

// KHR_mesh_quantization (listed as required when used): attributes written as small integers
// with meshoptimizer's quantisers instead of 32-bit floats. Ignored when Draco is enabled (Draco
// quantises by its own bits). Tangents, custom and instancing attributes stay FLOAT.
struct QuantizeOptions {
  bool enabled = false;
  // Per mesh (index into Scene::meshes): the bits B (1..16) of its POSITION grid; 0 or absent =
  // FLOAT positions. lo = the minimum corner of all the mesh's positions, extent = the largest
  // axis extent, step = extent / (2^B - 1) on every axis; POSITION is UNSIGNED_SHORT
  // meshopt_quantizeUnorm((x - lo) / extent, B) (stride 8). Every node drawing the mesh gets
  // translation lo and uniform scale step folded into its transform (its children the inverse),
  // so world positions stay within step / 2 per axis of the input. A mesh drawn by an
  // EXT_mesh_gpu_instancing node keeps FLOAT positions.
  std::vector<int> position_bits;
  // Per mesh, for meshes whose positions stay FLOAT (position_bits 0) in a meshopt file: the
  // largest distance (m) a vertex may move. > 0: POSITION goes through meshoptimizer's EXPONENTIAL
  // filter (meshopt_encodeFilterExp: per vertex a shared exponent and K-bit mantissas) with the
  // fewest K (1..24) whose decoded positions are all within this distance of the input (measured
  // by decoding); min/max are the decoded bounds. 0 or absent: exact floats.
  std::vector<double> float_position_error;
  // NORMAL, 1..16 bits: with meshopt octahedral (meshopt_encodeFilterOct, filter OCTAHEDRAL) in
  // BYTE (<= 8 bits) or SHORT components; without, meshopt_quantizeSnorm to 8 (<= 8) or 16 bits.
  // Normalized, stride 4 or 8.
  int normal_bits = 8;
  // TEXCOORD_0, 1..16 bits, UNSIGNED_SHORT normalized, when every coordinate is in [0, 1] (else
  // FLOAT). A primitive whose material has a texture, and all of whose material's primitives
  // have uvs in [0, 1], stores k = meshopt_quantizeUnorm(uv, B) and the material's texture
  // references get KHR_texture_transform (required) with scale 65535 / (2^B - 1), so the uv read
  // is k / (2^B - 1), within half a step (gltfpack's layout). Other uvs in [0, 1] (no texture) sit
  // on a grid of B-bit steps with the low 16 - B bits zero (meshopt_quantizeUnorm to B bits,
  // shifted): within half a B-bit step, one step in the top step (1.0 decodes as
  // (2^16 - 2^(16-B)) / 65535, 0.99977 for B = 12).
  int texcoord_bits = 12;
  // COLOR_0, 1..16 bits: UNSIGNED_BYTE (<= 8) or UNSIGNED_SHORT normalized, on the shifted grid.
  int color_bits = 8;
};

struct WriteOptions {
  FileFormat format = FileFormat::kGlb;
  DracoOptions draco;
  // EXT_meshopt_compression (meshopt_encode.h): kGlb only, not with Draco. Every attribute and
  // index view is compressed losslessly with meshoptimizer's codecs; the extension is required.
  // The JSON's numbers outside extras are printed as short as their floats and a primitive's
  // default mode 4 is left out (json_numbers.h: compact_gltf_numbers).
  bool meshopt = false;
  // With meshopt: the views of one kind — vertex attributes of one element type (stride,
  // component type, type) and filter, or indices of one primitive mode and index size — are
  // one view, compressed as one stream, each accessor at its offset in it (gltfpack's layout:
  // less JSON and fewer codec headers than one view per accessor). Decodes to the same values.
  bool meshopt_merge_views = false;
  QuantizeOptions quantize;
};

// The file's bytes (kGlb or kGltf; kGltfExternal throws: use encode_external). Throws GltfError.
std::string encode(const Scene& scene, const WriteOptions& options = {});
// The same bytes written to `out` as they are produced, without a second copy of the whole file
// in memory (a subdivided willow's GLB is ~800 MB). The caller checks `out`'s state for write
// errors. Throws GltfError.
void encode_to(const Scene& scene, std::ostream& out, const WriteOptions& options = {});

struct EncodedFile {
  std::string name;  // the uri, a plain file name
  std::string bytes;
};

// A .gltf whose buffers and images are files beside it. Buffer b is the file
// Scene::buffer_uris[b] and holds, in mesh and primitive order, the data of the primitives
// assigned to b (Primitive::buffer, else Mesh::buffer), then the instancing attributes of nodes
// whose mesh is in b; images without a uri go last into buffer 0. Each view is 4-byte aligned
// from the start of its buffer: so primitives encoded in two scenes, alone in a buffer of the
// same name in both, give the same .bin bytes (the lod stage relies on it).
// Every buffer must hold data. options.format is ignored. Throws GltfError.
struct EncodedFiles {
  std::string gltf;                    // the JSON text (pretty-printed, ends with a newline)
  std::vector<EncodedFile> resources;  // every buffer in order, then every written image with a uri
};
EncodedFiles encode_external(const Scene& scene, const WriteOptions& options = {});

// encode() and write to `path` (created or replaced). Throws GltfError.
void write_file(const Scene& scene, const std::filesystem::path& path, const WriteOptions& options = {});

// The file extension for a format: ".glb" or ".gltf".
const char* extension(FileFormat format);

}  // namespace sylva::gltf
