// The Assimp-backed reader on tiny OBJ, .mtl and PLY files held in memory: polygons
// triangulated and counted, degenerate faces dropped, missing normals left empty, colours
// clamped, Windows texture paths, welding, PLY, and bad input with its exact message.
#include <gtest/gtest.h>

#include "stages/import/mesh_frame.h"
#include "stages/import/mesh_import.h"
#include "stages/import/tests/mesh_test_files.h"
#include "tests/support/test_support.h"

namespace sylva::import {
namespace {

using testing::MapFiles;

MeshImport import_obj(const std::string& obj, MapFiles& files, MeshOptions o = {}) {
  o.recenter = false;
  return import_mesh(obj, "obj", "/m/t.obj", "t.obj", files, o);
}

std::string error_of(const std::string& bytes, const std::string& format, const std::string& name) {
  MapFiles files;
  try {
    import_mesh(bytes, format, "/m/" + name, name, files, {});
  } catch (const MeshError& e) {
    return e.what();
  }
  return "no error";
}

// A quad (2 triangles) and a pentagon (3 triangles), no normals: triangulated with a warning,
// normals left empty, the shared corners welded (7 positions, not 9).
TEST(MeshAssimp, QuadsAndNgonsTriangulated) {
  MapFiles files;
  const MeshImport m = import_obj(
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 3 0.5 0\nv 2 1 0\n"
      "f 1 2 3 4\nf 2 5 6 7 3\n",
      files);
  ASSERT_EQ(m.geometry.primitives.size(), 1u);
  const tree::SourcePrimitive& p = m.geometry.primitives[0];
  EXPECT_EQ(p.indices.size(), 15u);
  EXPECT_EQ(p.positions.size(), 7u);
  EXPECT_TRUE(p.normals.empty());
  EXPECT_TRUE(p.uvs.empty());
  EXPECT_EQ(m.warnings, (std::vector<std::string>{
                            "t.obj: warning: 1 quad(s) and 1 polygon(s) of more than 4 sides triangulated"}));
}

// A face with a repeated corner and one whose corners lie on a line are dropped, counted.
TEST(MeshAssimp, DegenerateFacesDropped) {
  MapFiles files;
  const MeshImport m = import_obj(
      "o twig\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
      "f 1 2 3\nf 1 2 2\nf 1 2 4\n",
      files);
  EXPECT_EQ(m.facts.triangles, 1u);
  EXPECT_EQ(m.warnings, (std::vector<std::string>{
                            "t.obj: warning: 2 degenerate triangle(s) (a repeated vertex or zero area) "
                            "dropped, in 't.obj/twig/twig'"}));
}

// Normals and uvs when the file has them (v flipped to glTF's top-left origin).
TEST(MeshAssimp, NormalsAndUvsRead) {
  MapFiles files;
  const MeshImport m = import_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 0.25\nvn 0 0 2\nf 1/1/1 2/2/1 3/3/1\n", files);
  const tree::SourcePrimitive& p = m.geometry.primitives[0];
  ASSERT_EQ(p.normals.size(), 3u);
  EXPECT_EQ(p.normals[0], (tree::Vec3f{0, 0, 1}));  // normalised
  ASSERT_EQ(p.uvs.size(), 3u);
  EXPECT_EQ(p.uvs[2], (std::array<float, 2>{0, 0.75f}));
}

// .mtl: a colour above 1 is clamped with a warning naming the material; a Windows absolute
// texture path is looked for beside the model, found, and kept as PNG bytes.
TEST(MeshAssimp, MtlColourClampedAndWindowsTextureFound) {
  MapFiles files;
  files.files["/m/t.mtl"] = "newmtl bark\nKd 1.5 0.5 0.25\nmap_Kd C:\\textures\\bark.png\n";
  files.files["/m/bark.png"] = testing::tiny_png();
  const MeshImport m = import_obj("mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl bark\nf 1 2 3\n", files);
  ASSERT_EQ(m.geometry.materials.size(), 1u);
  const tree::SourceMaterial& mat = m.geometry.materials[0];
  EXPECT_EQ(mat.name, "bark");
  EXPECT_EQ(mat.base_color, (std::array<float, 4>{1, 0.5f, 0.25f, 1}));
  ASSERT_EQ(m.geometry.images.size(), 1u);
  EXPECT_EQ(m.geometry.images[0].bytes, testing::tiny_png());
  EXPECT_EQ(m.geometry.images[0].name, "bark.png");
  EXPECT_EQ(mat.alpha_mode, tree::AlphaMode::kMask);  // an RGBA PNG: a leaf card's cut-out
  EXPECT_EQ(
      m.warnings,
      (std::vector<std::string>{
          "t.obj: warning: 'C:\\textures\\bark.png' is an absolute path or leaves the model's folder: "
          "looking for 'bark.png' beside the model instead",
          "t.obj: warning: material 'bark': colour, metallic, roughness or alpha cutoff outside [0, 1], "
          "clamped"}));
}

// An ASCII PLY with faces; up: z turns it Y up, scale multiplies.
TEST(MeshAssimp, PlyWithUpAxisAndScale) {
  MapFiles files;
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 0 2\n3 0 1 2\n";
  MeshOptions o;
  o.up = MeshUp::kZ;
  o.scale = 2;
  o.recenter = false;
  const MeshImport m = import_mesh(ply, "ply", "/m/t.ply", "t.ply", files, o);
  ASSERT_EQ(m.geometry.primitives.size(), 1u);
  EXPECT_EQ(m.geometry.primitives[0].positions[2], (tree::Vec3f{0, 4, 0}));
  EXPECT_EQ(m.facts.up, 'z');
  EXPECT_DOUBLE_EQ(m.facts.height, 4);
}

// Assimp is handed the name "<stem>.<format>": a PLY body in a file named .obj, read as PLY, has
// its header checked and is read by the PLY reader.
TEST(MeshAssimp, FormatNotExtensionPicksReaderAndChecks) {
  EXPECT_EQ(error_of("ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n",
                     "ply", "x.obj"),
            "x.obj: error: PLY header: 'element vertex 4000000000' declares more elements than the file's 75 "
            "bytes can hold");
  MapFiles files;
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const MeshImport m = import_mesh(ply, "ply", "/m/x.obj", "x.obj", files, {});
  EXPECT_EQ(m.facts.format, "ply");
  EXPECT_EQ(m.facts.triangles, 1u);
  // And an OBJ body in "x.ply", read as OBJ, goes to the OBJ reader, not to an unchecked PLY one.
  const MeshImport o =
      import_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "obj", "/m/x.ply", "x.ply", files, {});
  EXPECT_EQ(o.facts.triangles, 1u);
}

// A texture that exists but cannot be read: a MeshError naming the model, material and file, not
// fileio's FileReadError escaping the reader.
TEST(MeshAssimp, UnreadableTextureIsAMeshError) {
  struct Unreadable final : fileio::FileSource {
    MapFiles inner;
    std::string read(const std::filesystem::path& path) const override {
      if (path.extension() == ".png") throw fileio::FileReadError(path, "permission denied");
      return inner.read(path);
    }
    bool exists(const std::filesystem::path& path) const override {
      return path.extension() == ".png" || inner.exists(path);
    }
  } files;
  files.inner.files["/m/t.mtl"] = "newmtl bark\nmap_Kd bark.png\n";
  try {
    import_mesh("mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl bark\nf 1 2 3\n", "obj", "/m/t.obj", "t.obj",
                files, {});
    ADD_FAILURE() << "no error";
  } catch (const MeshError& e) {
    EXPECT_STREQ(
        e.what(),
        "t.obj: error: texture 'bark.png' of material 'bark': cannot read 'bark.png' (permission denied)");
  }
}

TEST(MeshAssimp, BadInputNamesTheFile) {
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "obj", "idx.obj"),
            "idx.obj: error: OBJ: vertex index out of range");
  EXPECT_EQ(error_of("", "obj", "empty.obj"), "empty.obj: error: empty file: nothing to import");
  EXPECT_EQ(error_of("v 0 0 0\n", "obj", "points.obj"), "points.obj: error: OBJ-file is too small.");
  EXPECT_EQ(
      error_of("ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n", "ply",
               "huge.ply"),
      "huge.ply: error: PLY header: 'element vertex 4000000000' declares more elements than the file's 75 "
      "bytes can hold");
  EXPECT_EQ(error_of("Kaydara FBX Binary  ", "fbx", "cut.fbx"),
            "cut.fbx: error: FBX-Tokenize (offset 0x0) file is too short");
}

// Collada: Assimp applies the file's <unit> and Z_UP itself; the trunk named by its node.
TEST(MeshAssimp, ColladaUnitAndAxisApplied) {
  MapFiles files;
  const std::string dae =
      test::read_file("stages/import/tests/data/triangle.dae");  // tests run in the source tree
  MeshOptions o;
  o.recenter = false;
  const MeshImport m = import_mesh(dae, "dae", "/m/t.dae", "t.dae", files, o);
  ASSERT_EQ(m.geometry.primitives.size(), 1u);
  EXPECT_NEAR(m.facts.height, 0.01, 1e-7);  // z = 1 cm became y = 0.01 m
  EXPECT_EQ(m.facts.up, 'y');
  EXPECT_EQ(m.geometry.primitives[0].name, "s/n/g");  // Collada nodes by their ids
}

// The same OBJ in two folders imports to the same geometry and, once the "<source>" prefix is
// the file name (as import_report.json writes it), the same warnings: no folder inside them.
TEST(MeshAssimp, SameBytesInTwoFoldersSameResult) {
  const std::string obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl bark\nf 1 2 3\n";
  MapFiles files;
  files.files["/a/t.mtl"] = files.files["/b/c/t.mtl"] = "newmtl bark\nKd 1 1 1\nmap_Kd ../gone.png\n";
  const auto run = [&](const std::string& path) {
    MeshOptions o;
    o.recenter = false;
    MeshImport m = import_mesh(obj, "obj", path, path, files, o);
    for (std::string& w : m.warnings) {
      EXPECT_EQ(w.rfind(path + ": ", 0), 0u) << w;
      w = "t.obj" + w.substr(path.size());
    }
    return m;
  };
  const MeshImport a = run("/a/t.obj"), b = run("/b/c/t.obj");
  EXPECT_EQ(a.geometry, b.geometry);
  EXPECT_EQ(a.warnings,
            (std::vector<std::string>{
                "t.obj: warning: '../gone.png' is an absolute path or leaves the model's folder: "
                "looking for 'gone.png' beside the model instead",
                "t.obj: warning: texture '../gone.png' of material 'bark' could not be read (no file "
                "'gone.png' beside the model): the material keeps its colour, without the texture"}));
  EXPECT_EQ(a.warnings, b.warnings);
}

}  // namespace
}  // namespace sylva::import
