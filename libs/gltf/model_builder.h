// Private to libs/gltf: gltf::Scene -> tinygltf::Model, in the fixed order writer.h ("Layout")
// describes: used materials, meshes (their primitives' attributes and indices), nodes, the scene,
// then the used images; extensions listed as the content needs them.
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "libs/gltf/scene.h"
#include "libs/gltf/writer.h"

namespace sylva::gltf::detail {

struct BuiltModel {
  // With kGltfExternal its buffers carry no data (`resources` has it) and images with a uri carry
  // neither a buffer view nor bytes.
  tinygltf::Model model;
  // The meshopt filter of each view whose bytes are filtered (view index -> "OCTAHEDRAL", ...).
  std::map<int, std::string> view_filters;
  // kGltfExternal: (uri, bytes) of every buffer in order, then of every image file; and each
  // buffer's byteLength (Scene::buffer_byte_lengths when given, else its data's size).
  std::vector<EncodedFile> resources;
  std::vector<std::size_t> buffer_sizes;
};

// `scene` must pass validate_scene(). Throws GltfError on bad quantisation options, an external
// buffer without data or uri, a declared buffer length below the data, or a Draco failure.
BuiltModel build_model(const Scene& scene, const WriteOptions& options);

}  // namespace sylva::gltf::detail
