// What `sylva lodcheck` adds to libs/check/view_check.h for the lod stage's files.
#include "stages/lod/check/lodcheck.h"

#include <string>

namespace sylva::lod {

render::Scene branches_only(const render::Scene& scene) {
  render::Scene out = scene;
  for (auto& mesh : out.meshes) {
    std::erase_if(mesh.primitives, [&](const render::Primitive& p) {
      if (p.material < 0 || p.material >= static_cast<int>(scene.materials.size())) return true;
      const std::string& name = scene.materials[static_cast<std::size_t>(p.material)].name;
      return name != "bark" && name != "bark_lines";
    });
  }
  return out;
}

}  // namespace sylva::lod
