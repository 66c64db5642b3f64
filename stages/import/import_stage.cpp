// The adapter of stage `import`: declares the parameters, reads the one input file (at most
// kMaxMeshFileBytes), calls the core (import_file.h) and writes tree.sylt and import_report.json.
// Every input problem becomes a StageError whose message names the file and line (text formats),
// byte (.sylt) or element (meshes). A mesh's sidecar files are read through ctx.files().
#include "stages/import/import_stage.h"

#include <nlohmann/json.hpp>

#include "libs/tree/sylt_format.h"
#include "stages/import/import_error.h"
#include "stages/import/import_file.h"

namespace sylva {

namespace {

// 2: writes .sylt version 2 (leaf kind, atlas, bark tint); 3: mesh formats, import_report.json,
// `up: auto`, `node`.
constexpr int kOwnVersion = 3;

// import_report.json: the format, the warnings (the file named by its file name, so the bytes do
// not depend on where the file lies) and, for a mesh, the facts of its conversion.
std::string report(const import::ImportResult& r, const std::string& source, const std::string& file_name) {
  nlohmann::json j;
  j["file"] = file_name;
  j["format"] = import::format_name(r.format);
  nlohmann::json warnings = nlohmann::json::array();
  for (const std::string& w : r.warnings)
    warnings.push_back(w.rfind(source, 0) == 0 ? file_name + w.substr(source.size()) : w);
  j["warnings"] = warnings;
  if (import::is_mesh_format(r.format)) {
    const tree::SourceGeometry& g = r.tree.source;
    std::size_t triangles = 0;
    for (const auto& p : g.primitives) triangles += p.indices.size() / 3;
    j["mesh"] = {{"unit", r.mesh.unit},
                 {"unit_scale", r.mesh.unit_scale},
                 {"up_axis", std::string(1, r.mesh.up)},
                 {"primitives", g.primitives.size()},
                 {"vertices", r.mesh.vertices},
                 {"triangles", triangles},
                 {"materials", g.materials.size()},
                 {"images", g.images.size()},
                 {"height_m", r.mesh.height}};
  }
  return j.dump(2) + "\n";
}

class ImportStage final : public Stage {
 public:
  ImportStage() {
    info_.name = "import";
    // Own version 2 (the .sylt it writes went to version 2), times ten, plus the .sylt format
    // version: a new .sylt format changes this stage's key even if nobody bumps kOwnVersion.
    info_.version = 10 * kOwnVersion + static_cast<int>(tree::kSyltVersion);
    info_.summary =
        "read a tree skeleton: QSM cylinder tables (TreeQSM, SimpleForest, rTwig, aRchi), "
        ".sylt, or a text skeleton; or a tree mesh (glTF/GLB, OBJ, FBX, DAE, 3DS, PLY) into the "
        "tree's source geometry";
    info_.params = {
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
    info_.inputs = InputSpec{{}, 0, 0, "none: the file parameter is the input"};
    info_.output_type = "tree";
    info_.outputs = {"tree.sylt", "import_report.json"};
  }

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    const std::string source = ctx.param_file("file").string();
    const std::string bytes = ctx.read_param_file("file", {}, import::kMaxMeshFileBytes);

    import::ImportOptions options;
    options.format = ctx.string("format");
    for (const Value& v : ctx.param("columns").as_list()) options.columns.push_back(v.as_string());
    const std::string& up = ctx.string("up");
    options.qsm.up = up == "y" ? import::UpAxis::kY : import::UpAxis::kZ;
    options.qsm.scale = ctx.real("scale");
    options.qsm.recenter = ctx.boolean("recenter");
    options.mesh.up = up == "y" ? import::MeshUp::kY : up == "z" ? import::MeshUp::kZ : import::MeshUp::kAuto;
    options.mesh.scale = ctx.real("scale");
    options.mesh.recenter = ctx.boolean("recenter");
    options.mesh.node = ctx.string("node");
    options.files = &ctx.files();

    import::ImportResult result;
    try {
      result = import::import_file(bytes, source, options);
    } catch (const import::ImportError& e) {
      throw StageError(e.what());
    } catch (const import::MeshError& e) {
      throw StageError(e.what());
    } catch (const tree::TreeFormatError& e) {
      throw StageError(e.what());
    } catch (const std::invalid_argument& e) {
      throw StageError(e.what());
    }
    ctx.check_cancelled();
    ctx.write_output("tree.sylt", tree::encode_sylt(result.tree));
    ctx.write_output("import_report.json",
                     report(result, source, std::filesystem::path(source).filename().string()));
  }

 private:
  StageInfo info_;
};

}  // namespace

std::unique_ptr<Stage> make_import_stage() { return std::make_unique<ImportStage>(); }

}  // namespace sylva
