// What stage `import` declares: the parameters of import_stage.cpp's adapter.
#include "stages/import/import_info.h"

#include "libs/tree/sylt_format.h"

namespace sylva {

namespace {

// 2: writes .sylt version 2 (leaf kind, atlas, bark tint); 3: mesh formats, import_report.json,
// `up: auto`, `node`.
constexpr int kOwnVersion = 3;

}  // namespace

StageInfo import_stage_info() {
  StageInfo info;
  info.name = "import";
  // The own version times ten, plus the .sylt format version: a new .sylt format changes this
  // stage's key even if nobody bumps kOwnVersion.
  info.version = 10 * kOwnVersion + static_cast<int>(tree::kSyltVersion);
  info.summary =
      "read a tree skeleton: QSM cylinder tables (TreeQSM, SimpleForest, rTwig, aRchi), "
      ".sylt, or a text skeleton; or a tree mesh (glTF/GLB, OBJ, FBX, DAE, 3DS, PLY) into the "
      "tree's source geometry";
  info.params = {
      // A mesh file's companions (.bin, .mtl, textures) are below its folder: the whole folder
      // is this node's input (docs/recipes.md). .glb and .ply are self-contained as a rule but
      // may name external images too, so they are included; QSM tables, .sylt and text
      // skeletons are read alone.
      Param::path("file")
          .with_folder_for({".gltf", ".glb", ".obj", ".fbx", ".dae", ".3ds", ".ply"})
          .describe("the file to import (a mesh file brings its folder: docs/recipes.md)"),
      Param::choice(
          "format",
          {"auto", "qsm", "treeqsm_txt", "skeleton_txt", "sylt", "gltf", "obj", "fbx", "dae", "3ds", "ply"},
          "auto")
          .describe("file format; auto detects it from the content and the file name"),
      Param::string_list("columns", Value::List{})
          .describe("column names of a headerless TreeQSM table, in order (default: TreeQSM's "
                    "radius length start(3) axis(3) parent extension branch branch_order)"),
      Param::choice("up", {"auto", "z", "y"}, "auto")
          .describe("the file's up axis, converted to sylva's Y up; auto: z for QSM tables (their "
                    "convention), the file's own for meshes (glTF y, FBX its UpAxis, others y)"),
      Param::real("scale", 1.0)
          .range(1e-6, 1e6)
          .describe("multiplies the file's units to get metres (after a mesh's own unit, FBX), e.g. "
                    "0.001 for a QSM table in millimetres"),
      Param::boolean("recenter", true)
          .describe("move a QSM tree so its root cylinder starts at the origin; a mesh so its trunk "
                    "foot (the bottom-most vertices' centre) is at the origin on y = 0"),
      Param::string("node", "")
          .describe("meshes: import only the subtree of the node of this name (a file with several "
                    "trees); empty: the whole default scene"),
  };
  info.inputs = InputSpec{{}, 0, 0, "none: the file parameter is the input"};
  info.output_type = "tree";
  info.outputs = {"tree.sylt", "import_report.json"};
  return info;
}

}  // namespace sylva
