// The adapter of stage `import`: declares the parameters, reads the one input file, calls the
// core (import_file.h) and writes tree.sylt. Every input problem becomes a StageError whose
// message names the file and line (text formats) or byte (.sylt).
#include "stages/import/import_stage.h"

#include "libs/tree/sylt_format.h"
#include "stages/import/import_error.h"
#include "stages/import/import_file.h"

namespace sylva {

namespace {

constexpr int kOwnVersion = 2;  // 2: writes .sylt version 2 (leaf kind, atlas, bark tint)

class ImportStage final : public Stage {
 public:
  ImportStage() {
    info_.name = "import";
    // Own version 2 (the .sylt it writes went to version 2), times ten, plus the .sylt format
    // version: a new .sylt format changes this stage's key even if nobody bumps kOwnVersion.
    info_.version = 10 * kOwnVersion + static_cast<int>(tree::kSyltVersion);
    info_.summary =
        "read a tree skeleton: QSM cylinder tables (TreeQSM, SimpleForest, rTwig, aRchi), "
        ".sylt, or a text skeleton";
    info_.params = {
        // A mesh file's companions (.bin, .mtl, textures) are below its folder: the whole folder
        // is this node's input (docs/recipes.md). .glb and .ply are self-contained as a rule but
        // may name external images too, so they are included; QSM tables, .sylt and text
        // skeletons are read alone.
        Param::path("file")
            .with_folder_for({".gltf", ".glb", ".obj", ".fbx", ".dae", ".3ds", ".ply"})
            .describe("the file to import (a mesh file brings its folder: docs/recipes.md)"),
        Param::choice("format", {"auto", "qsm", "treeqsm_txt", "skeleton_txt", "sylt"}, "auto")
            .describe("file format; auto detects it from the content and the file name"),
        Param::string_list("columns", Value::List{})
            .describe("column names of a headerless TreeQSM table, in order (default: TreeQSM's "
                      "radius length start(3) axis(3) parent extension branch branch_order)"),
        Param::choice("up", {"z", "y"}, "z")
            .describe("up axis of a QSM table; z (QSM's convention) is converted to sylva's Y up"),
        Param::real("scale", 1.0)
            .range(1e-6, 1e6)
            .describe("QSM units to metres, e.g. 0.001 for millimetres"),
        Param::boolean("recenter", true)
            .describe("move a QSM tree so its root cylinder starts at the origin"),
    };
    info_.inputs = InputSpec{{}, 0, 0, "none: the file parameter is the input"};
    info_.output_type = "tree";
    info_.outputs = {"tree.sylt"};
  }

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    const std::string source = ctx.param_file("file").string();
    const std::string bytes = ctx.read_param_file("file");

    import::ImportOptions options;
    options.format = ctx.string("format");
    for (const Value& v : ctx.param("columns").as_list()) options.columns.push_back(v.as_string());
    options.qsm.up = ctx.string("up") == "y" ? import::UpAxis::kY : import::UpAxis::kZ;
    options.qsm.scale = ctx.real("scale");
    options.qsm.recenter = ctx.boolean("recenter");

    tree::Tree result;
    try {
      result = import::import_tree(bytes, source, options);
    } catch (const import::ImportError& e) {
      throw StageError(e.what());
    } catch (const tree::TreeFormatError& e) {
      throw StageError(e.what());
    } catch (const std::invalid_argument& e) {
      throw StageError(e.what());
    }
    ctx.check_cancelled();
    ctx.write_output("tree.sylt", tree::encode_sylt(result));
  }

 private:
  StageInfo info_;
};

}  // namespace

std::unique_ptr<Stage> make_import_stage() { return std::make_unique<ImportStage>(); }

}  // namespace sylva
