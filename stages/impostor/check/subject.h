// An impostor artifact as the check draws it: impostor.json (libs/impostor), its two maps and
// impostor.glb, read from the files of a built `impostor` node.
#pragma once

#include <filesystem>

#include "stages/impostor/check/impostorcheck.h"

namespace sylva::impostor {

// Reads `dir`/impostor.json and the files it names (impostor.glb for billboards). Throws
// ImpostorFormatError, image::ImageError or render::SceneLoadError, each naming the file.
ImpostorSubject load_impostor_subject(const std::filesystem::path& dir, const std::string& label);

// The drawable form of an octahedral impostor from its description and maps.
render::OctahedralImpostor octahedral_of(const ImpostorInfo& info, image::Image color,
                                         image::Image normal_depth);

}  // namespace sylva::impostor
