// The full-detail model of a lod node (full_detail.h): read from the node's own full.glb, never
// rebuilt here, so it cannot drift from the stage's options (card seeds, atlas opacity, ...).
#include "app/full_detail.h"

#include <stdexcept>
#include <utility>

#include "libs/gltf/reader.h"
#include "libs/gltf/writer.h"
#include "libs/render/gltf_scene.h"

namespace sylva {

namespace {
constexpr const char* kFullDetailFile = "full.glb";  // stages/lod/lod_stage.cpp writes it
}  // namespace

std::filesystem::path lod_full_detail_file(const Recipe& recipe, const RecipeBuild& built,
                                           const std::string& lod_node) {
  const InputArtifact lod = input_artifact(recipe, built, lod_node);
  const ArtifactFile* full = lod.file(kFullDetailFile);
  if (!full) throw std::runtime_error("input '" + lod_node + "' has no " + kFullDetailFile);
  return full->path;
}

std::string read_lod_full_detail(const Recipe& recipe, const RecipeBuild& built, const std::string& lod_node,
                                 CommandContext& ctx) {
  const std::filesystem::path path = lod_full_detail_file(recipe, built, lod_node);
  std::string why;
  std::optional<std::string> bytes = ctx.fs.read(path, &why);
  if (!bytes) throw std::runtime_error(path.string() + ": " + why);
  return std::move(*bytes);
}

render::Scene lod_full_detail_scene(const Recipe& recipe, const RecipeBuild& built,
                                    const std::string& lod_node, CommandContext& ctx) {
  return render::load_gltf_scene_from_memory(read_lod_full_detail(recipe, built, lod_node, ctx),
                                             lod_node + " (full detail)");
}

std::string branches_only_glb(const std::filesystem::path& full_glb) {
  gltf::Scene scene = gltf::read_scene(full_glb);
  for (gltf::Mesh& mesh : scene.meshes)
    std::erase_if(mesh.primitives, [&](const gltf::Primitive& p) {
      if (p.material < 0 || p.material >= static_cast<int>(scene.materials.size())) return true;
      const std::string& name = scene.materials[static_cast<std::size_t>(p.material)].name;
      return name != "bark" && name != "bark_lines";
    });
  return gltf::encode(scene);
}

}  // namespace sylva
