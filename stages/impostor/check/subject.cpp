// Reading a built impostor for the check (subject.h).
#include "stages/impostor/check/subject.h"

#include "libs/image/image_io.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/impostor_atlas.h"

namespace sylva::impostor {

render::OctahedralImpostor octahedral_of(const ImpostorInfo& info, image::Image color,
                                         image::Image normal_depth) {
  render::OctahedralImpostor o;
  o.color = std::move(color);
  o.normal_depth = std::move(normal_depth);
  o.geometry = render::impostor_geometry(info);
  return o;
}

ImpostorSubject load_impostor_subject(const std::filesystem::path& dir, const std::string& label) {
  ImpostorSubject s;
  s.label = label;
  s.info = read_impostor_json((dir / kImpostorJsonFile).string());
  if (s.info.kind == Kind::kBillboards) {
    s.cards = render::load_gltf_scene(dir / kImpostorGlbFile);
  } else {
    s.octahedral = octahedral_of(s.info, image::read_image(dir / s.info.color_map),
                                 image::read_image(dir / s.info.normal_depth_map));
  }
  return s;
}

}  // namespace sylva::impostor
