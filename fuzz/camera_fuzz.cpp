// libFuzzer target: camera-set files (libs/render/camera.h, docs/renderer.md). Contract:
// parse_camera_set returns a set or throws CameraSetError listing at least one error, each with
// text.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "libs/render/camera.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sylva;
  try {
    (void)render::parse_camera_set(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.yaml");
  } catch (const render::CameraSetError& e) {
    if (e.errors().empty()) fuzz::fail("CameraSetError without errors");
    for (const auto& line : e.errors())
      if (line.empty()) fuzz::fail("CameraSetError with an empty error line");
  } catch (const std::exception& e) {
    fuzz::fail(std::string("parse_camera_set threw an undocumented error: ") + e.what());
  }
  return 0;
}
