// Fuzz-style robustness of the mesh readers (the fuzz targets' contract, deterministic): the
// committed seeds of fuzz/corpus/mesh_gltf and mesh_assimp, truncated and with bytes flipped,
// either import to valid geometry or fail with one MeshError naming the file.
#include <gtest/gtest.h>

#include <filesystem>

#include "libs/tree/source_geometry.h"
#include "stages/import/mesh_import.h"
#include "stages/import/tests/mesh_test_files.h"
#include "tests/support/test_support.h"

namespace sylva::import {
namespace {

namespace fs = std::filesystem;

// "ok" or "error"; anything else fails the test.
std::string check_one(const std::string& bytes, const std::string& format) {
  testing::MapFiles none;
  MeshOptions o;
  o.max_vertices = o.max_triangles = 1 << 20;
  try {
    const MeshImport m = import_mesh(bytes, format, "/fuzz/f." + format, "f." + format, none, o);
    EXPECT_EQ(tree::validate_source_geometry(m.geometry), std::vector<std::string>{});
    return "ok";
  } catch (const MeshError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("f." + format + ": error: ", 0), 0u) << e.what();
    return "error";
  }
}

TEST(MeshFuzz, SeedsTruncatedAndMutated) {
  const fs::path root = fs::path("fuzz") / "corpus";     // tests run in the source tree
  static const char* const kFormats[] = {"obj", "ply"};  // as fuzz_mesh_assimp
  test::XorShift64 rng(37);
  std::size_t runs = 0;
  for (const char* dir : {"mesh_gltf", "mesh_assimp"}) {
    ASSERT_TRUE(fs::exists(root / dir)) << root / dir;
    for (const auto& entry : fs::directory_iterator(root / dir)) {
      std::string bytes = test::read_file(entry.path());
      std::string format = "gltf";
      if (std::string(dir) == "mesh_assimp") {
        format = kFormats[std::uint8_t(bytes[0]) % 2];
        bytes.erase(0, 1);
      }
      EXPECT_EQ(check_one(bytes, format), "ok") << entry.path();
      for (std::size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 16, ++runs)
        check_one(bytes.substr(0, cut), format);
      for (int i = 0; i < 40; ++i, ++runs) {
        std::string m = bytes;
        for (int k = 0; k < 3; ++k) m[rng() % m.size()] = char(rng() & 0xff);
        check_one(m, format);
      }
    }
  }
  EXPECT_GT(runs, 200u);
}

}  // namespace
}  // namespace sylva::import
