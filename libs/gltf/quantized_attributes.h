// Private to libs/gltf: KHR_mesh_quantization (writer.h, QuantizeOptions): the plan (each mesh's
// position grid, each material's texcoord grid) and the integer (or exponentially filtered)
// vertex attributes written with meshoptimizer's quantisers.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "libs/gltf/accessor_writer.h"
#include "libs/gltf/scene.h"
#include "libs/gltf/writer.h"

namespace sylva::gltf::detail {

// A mesh's position grid (QuantizeOptions::position_bits); bits 0 = FLOAT positions.
struct PositionGrid {
  int bits = 0;
  std::array<double, 3> lo{0, 0, 0};  // minimum corner of all the mesh's positions
  double extent = 0, step = 1;        // largest axis extent; extent / (2^bits - 1) (1 when flat)
};

struct QuantizePlan {
  std::vector<PositionGrid> grids;  // per mesh
  // Per material: its uvs go on the texcoord grid, undone by KHR_texture_transform (textured,
  // and every primitive drawn with it has uvs in [0, 1]).
  std::vector<char> uv_grid;
};

// Checks the options (GltfError naming the bad one) and plans every mesh and material of
// `scene`. Meshes drawn by an instancing node keep FLOAT positions.
QuantizePlan plan_quantization(const Scene& scene, const QuantizeOptions& q);

// Whether every value is in [0, 1].
bool in_unit_range(const std::vector<float>& v);

// Writes quantised attributes through `views` (not owned); each returns the accessor index.
class AttributeQuantizer {
 public:
  // `meshopt`: the file is meshopt-compressed (normals go through the OCTAHEDRAL filter).
  AttributeQuantizer(AccessorWriter& views, const QuantizeOptions& q, bool meshopt)
      : views_(views), q_(q), meshopt_(meshopt) {}

  // POSITION on the mesh's grid: UNSIGNED_SHORT xyz + 2 padding bytes, with integer min/max.
  int grid_positions(const std::vector<float>& v, const PositionGrid& g);
  // FLOAT POSITION through the EXPONENTIAL filter with the fewest mantissa bits that keep every
  // vertex within max_error (QuantizeOptions::float_position_error); min/max of what decodes.
  int exponential_positions(const std::vector<float>& v, double max_error);
  // NORMAL: octahedral through meshopt's filter when the file is meshopt-compressed, else
  // per-component snorm; BYTE or SHORT normalized VEC3 padded to 4 components.
  int normals(const std::vector<float>& v);
  // TEXCOORD_0 of a material with a uv grid: UNSIGNED_SHORT normalized k = meshopt_quantizeUnorm(uv,
  // B), which the material's KHR_texture_transform scales from k / 65535 to k / (2^B - 1).
  int grid_texcoords(const std::vector<float>& v);
  // Unsigned normalized values in [0, 1] (texcoords, colours): `bits` bits widened to 8 or 16.
  int unorm(const std::vector<float>& v, int components, int bits, bool allow_byte);

  // Whether an integer attribute was written (the file then uses KHR_mesh_quantization).
  bool wrote_integers() const { return wrote_integers_; }

 private:
  int integer_attribute(const void* bytes, std::size_t count, std::size_t stride, int component_type,
                        int components, bool normalized);

  AccessorWriter& views_;
  const QuantizeOptions& q_;
  bool meshopt_;
  bool wrote_integers_ = false;
};

}  // namespace sylva::gltf::detail
