// libFuzzer target: glTF/GLB import (libs/render/gltf_scene.h: tinygltf, Draco, sylva's own
// checks of indices, accessors and textures). External uris resolve against a directory that
// does not exist, so the target reads no file. Contract: load_gltf_scene_from_memory returns a
// scene or throws SceneLoadError with a message.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_check.h"
#include "libs/render/gltf_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sylva;
  try {
    (void)render::load_gltf_scene_from_memory(std::string(reinterpret_cast<const char*>(data), size),
                                              "fuzz.glb", "/nonexistent-sylva-fuzz-dir");
  } catch (const render::SceneLoadError& e) {
    fuzz::expect_message(e.what());
  } catch (const std::exception& e) {
    fuzz::fail(std::string("load_gltf_scene_from_memory threw an undocumented error: ") + e.what());
  }
  return 0;
}
