// Private to libs/gltf: one TRIANGLES primitive -> a Draco mesh bitstream (KHR_draco_mesh_compression).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "libs/gltf/scene.h"
#include "libs/gltf/writer.h"

namespace sylva::gltf::detail {

struct DracoEncoded {
  std::string bytes;       // the bitstream for the extension's buffer view
  std::size_t points = 0;  // vertex count the decoder returns (accessor counts)
  std::size_t faces = 0;   // triangle count the decoder returns
  // glTF attribute name -> Draco attribute unique id, in glTF attribute order.
  std::vector<std::pair<std::string, int>> attribute_ids;
};

// Encodes positions, normals, tangents (generic), texcoords, colors and custom attributes of a
// TRIANGLES primitive (indexed or not); tangents only when `with_tangents` (the writer's
// normal-map rule, writer.h). Throws GltfError when Draco fails.
DracoEncoded encode_draco(const Primitive& p, const DracoOptions& options, bool with_tangents);

}  // namespace sylva::gltf::detail
