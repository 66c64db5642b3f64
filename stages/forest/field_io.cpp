#include "stages/forest/field_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>

namespace sylva::forest {

Field read_field(const std::string& bytes, const std::string& name, double x0, double z0, double x1,
                 double z1) {
  auto fail = [&](const std::string& why) { throw std::runtime_error(name + ": " + why); };
  // Decoded from memory: the stage read the file through its context (its declared input).
  OIIO::Filesystem::IOMemReader memory(bytes.data(), bytes.size());
  auto in = OIIO::ImageInput::open(name, nullptr, &memory);
  if (!in) {
    std::string m = OIIO::geterror();
    for (char& c : m)
      if (c == '\n') c = ' ';
    fail("cannot read image: " + m);
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 2 || spec.height < 2) fail("a map needs at least 2 x 2 pixels");
  // Read as floats: 16384 x 16384 is 1 GiB, and a header may declare any size.
  if (double(spec.width) * double(spec.height) > 16384.0 * 16384.0)
    fail("a map of " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
         " pixels is larger than the 16384 x 16384 a map may have");
  Field f;
  f.cols = spec.width;
  f.rows = spec.height;
  f.x0 = x0;
  f.z0 = z0;
  f.x1 = x1;
  f.z1 = z1;
  f.values.resize(std::size_t(f.cols) * std::size_t(f.rows));
  // Channel 0 only, converted to float (integer types normalised to [0, 1] by OIIO).
  if (!in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, f.values.data()))
    fail("cannot decode image: " + in->geterror());
  in->close();
  for (float v : f.values)
    if (!std::isfinite(v) || v < 0 || v > 1)
      fail("a value lies outside [0, 1] (float maps must be normalised)");
  return f;
}

}  // namespace sylva::forest
