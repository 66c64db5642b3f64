// libFuzzer target: stage import's Assimp reader (stages/import/mesh_assimp.h through
// import_mesh). The first input byte picks the format (mod 2: obj, ply), the rest is the file,
// at most 64 KiB (Assimp's readers allocate from counts in the file; with the PLY
// header check and the vertex limit below, a small input cannot ask for unbounded memory). The
// sidecar source holds no files. Collada, FBX and 3DS are left out: Debian's Assimp 5.2.5
// Collada reader segfaults on mutated files (found 2026-12-08 by stages/import/tests/
// mesh_fuzz_test.cpp), a bug of the library sylva cannot catch. Contract: geometry that passes
// validate_source_geometry, or MeshError with a message.
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
  if (size == 0 || size > 64 * 1024) return 0;
  static const char* const kFormats[] = {"obj", "ply"};
  const std::string format = kFormats[data[0] % 2];
  import::MeshOptions options;
  options.max_vertices = options.max_triangles = std::size_t(1) << 20;
  try {
    const import::MeshImport m = import::import_mesh(
        std::string(reinterpret_cast<const char*>(data) + 1, size - 1), format,
        "/nonexistent-sylva-fuzz-dir/fuzz." + format, "fuzz." + format, fuzz::NoFiles(), options);
    if (!tree::validate_source_geometry(m.geometry).empty())
      fuzz::fail("import_mesh returned invalid geometry");
  } catch (const import::MeshError& e) {
    fuzz::expect_message(e.what());
  } catch (const std::exception& e) {
    fuzz::fail(std::string("import_mesh threw an undocumented error: ") + e.what());
  }
  return 0;
}
