// libFuzzer target: stage import's glTF reader (stages/import/mesh_gltf.h through import_mesh:
// tinygltf, libs/render's accessor, Draco and meshopt helpers, the checks and the frame). The
// sidecar source holds no files, so the target reads none. Contract: import_mesh returns
// geometry that passes validate_source_geometry, or throws MeshError with a message.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_check.h"
#include "fuzz/no_files.h"
#include "libs/fileio/file_source.h"
#include "libs/tree/source_geometry.h"
#include "stages/import/mesh_import.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sylva;
  if (size > (std::size_t(1) << 20)) return 0;
  import::MeshOptions options;
  options.max_vertices = options.max_triangles = std::size_t(1) << 20;  // bounded memory
  try {
    const import::MeshImport m =
        import::import_mesh(std::string(reinterpret_cast<const char*>(data), size), "gltf",
                            "/nonexistent-sylva-fuzz-dir/fuzz.glb", "fuzz.glb", fuzz::NoFiles(), options);
    if (!tree::validate_source_geometry(m.geometry).empty())
      fuzz::fail("import_mesh returned invalid geometry");
  } catch (const import::MeshError& e) {
    fuzz::expect_message(e.what());
  } catch (const std::exception& e) {
    fuzz::fail(std::string("import_mesh threw an undocumented error: ") + e.what());
  }
  return 0;
}
