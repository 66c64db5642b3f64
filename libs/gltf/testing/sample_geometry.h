// Test helper: small pieces of glTF scenes that several of libs/gltf's and libs/render's tests
// build from. Not part of libs/gltf's API; linked only by tests (sylva_gltf_testing).
#pragma once

#include <string>
#include <vector>

#include "libs/gltf/scene.h"

namespace sylva::gltf::testing {

// A node named `name` drawing mesh `mesh` (-1: none) with the given children.
Node make_node(std::string name, int mesh = -1, std::vector<int> children = {});

// A wavy grid of n x n quads over [0, 1]^2 in x-z (height 0.1 sin(7x) cos(5z)): (n + 1)^2
// vertices in rows of n + 1 with up normals and uvs (x, z), two triangles a quad, quads in row
// order. n >= 1.
Primitive wavy_grid(int n);

}  // namespace sylva::gltf::testing
