// The adapter of stage `import`: declares the parameters, reads the one input file (at most
// kMaxMeshFileBytes), calls the core (import_file.h) and writes tree.sylt and import_report.json.
// Every input problem becomes a StageError whose message names the file and line (text formats),
// byte (.sylt) or element (meshes). A mesh's sidecar files are read through ctx.files().
#include "stages/import/import_stage.h"

#include <nlohmann/json.hpp>

#include "libs/tree/sylt_format.h"
#include "stages/import/import_error.h"
#include "stages/import/import_file.h"
#include "stages/import/import_info.h"

namespace sylva {

namespace {

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
  ImportStage() : info_(import_stage_info()) {}

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
