// The full-detail model of a built lod node, as the lod stage wrote it: the node's full.glb
// (stages/lod/lod_gltf.h encode_full_detail: the chain at epsilon = 0, every branch a mesh, every
// leaf and needle, written like level 0 with the atlas embedded). What `sylva lodcheck` and
// `sylva impostorcheck` measure LOD levels and impostors against, read as written, so a check
// judges against exactly what the stage built (and what the pack stage measures with).
#pragma once

#include <filesystem>
#include <string>

#include "app/command_context.h"
#include "app/recipe_build.h"
#include "libs/render/scene.h"
#include "pipeline/recipe.h"

namespace sylva {

// The path of built lod node `lod_node`'s full.glb. Throws std::runtime_error ("input 'N' has
// no full.glb") when the node's outputs hold none.
std::filesystem::path lod_full_detail_file(const Recipe& recipe, const RecipeBuild& built,
                                           const std::string& lod_node);

// The bytes of lod node `lod_node`'s full.glb, read through ctx.fs. Throws std::runtime_error
// with the path and the reason when it cannot be read.
std::string read_lod_full_detail(const Recipe& recipe, const RecipeBuild& built, const std::string& lod_node,
                                 CommandContext& ctx);

// The full-detail model as a scene named "<lod_node> (full detail)" in messages. Throws
// std::exception with a one-line message when it cannot be read or decoded.
render::Scene lod_full_detail_scene(const Recipe& recipe, const RecipeBuild& built,
                                    const std::string& lod_node, CommandContext& ctx);

// The GLB of `full_glb` (a full.glb's path) without leaves and needles: only the primitives of
// materials "bark" and "bark_lines" kept (as stages/lod/check/lodcheck.h branches_only keeps them
// in a scene), the materials and images nothing uses left out by the writer (docs/gltf.md) —
// the file encode_full_detail writes with branches_only. Throws std::exception (gltf::ReadError,
// gltf::GltfError) with a one-line message.
std::string branches_only_glb(const std::filesystem::path& full_glb);

}  // namespace sylva
