// Composing scenes: the nodes, meshes, materials and images of one scene appended to another, as
// stage `pack` builds a species' MSFT_lod chain from the level files it keeps (and the impostor).
//
// Contract: append_scene(into, from) adds every node, mesh, material and image of `from` to
// `into` with their indices shifted, and returns the new indices of `from`'s root nodes (they are
// NOT added to into.roots: the caller decides). An image of `from` whose name, media type and
// bytes equal an image already in `into` is not added again (its uses point at the existing one);
// likewise a material equal in every field (after that remapping). Scene-level fields of `into`
// (generator, extras, extensions_required, buffer_uris) are kept; `from`'s
// extensions_required are added when missing. Primitive::buffer and Mesh::buffer are reset to the
// defaults (they index `from`'s buffer_uris, which are not carried over).
#pragma once

#include <vector>

#include "libs/gltf/scene.h"

namespace sylva::gltf {

std::vector<int> append_scene(Scene& into, const Scene& from);

}  // namespace sylva::gltf
