// Reading a height map or density map image into a Field (fields.h) with OpenImageIO: 16-bit PNG,
// EXR, TIFF, 8-bit PNG, ... (the first channel; integer formats normalised to [0, 1], float
// formats taken as they are and required to lie in [0, 1]: scale heights with height_range_m).
// This is why the forest stage is a heavy stage (docs/architecture.md, "Heavy libraries load
// lazily"): its core stays free of OpenImageIO.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "stages/forest/fields.h"

namespace sylva::forest {

// The image in `bytes` (the file `name`, whose extension picks the format). Throws
// std::runtime_error("<name>: <reason>") for undecodable images, images smaller than 2 x 2 or
// larger than 16384 x 16384 pixels, and float values outside [0, 1]. The field covers
// [x0, x1] x [z0, z1].
Field read_field(const std::string& bytes, const std::string& name, double x0, double z0, double x1,
                 double z1);

}  // namespace sylva::forest
