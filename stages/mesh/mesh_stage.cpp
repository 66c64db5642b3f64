// The adapter of stage `mesh`: declares the parameters, reads the upstream tree artifact
// (tree.sylt and the textures it names), runs the core (tree_mesh.h) and writes one glTF file
// through libs/gltf. Seed: Nystad 2010 §4.3 and §5.3 (the core says which part is where).
#include "stages/mesh/mesh_stage.h"

#include <nlohmann/json.hpp>

#include "libs/gltf/writer.h"
#include "libs/sourcegltf/source_scene.h"
#include "libs/tree/sylt_format.h"
#include "stages/mesh/mesh_info.h"
#include "stages/mesh/tree_mesh.h"

namespace sylva {

namespace {

class MeshStage final : public Stage {
 public:
  MeshStage() : info_(mesh_stage_info()) {}

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    // 1. Read the tree and the textures it names from the one input artifact.
    const InputArtifact& in = ctx.inputs().front();
    const ArtifactFile* sylt = in.file("tree.sylt");
    if (!sylt) throw StageError("input '" + in.node + "' has no tree.sylt");
    tree::Tree tree;
    try {
      tree = tree::decode_sylt(ctx.read_input(*sylt), sylt->path.string());
    } catch (const tree::TreeFormatError& e) {
      throw StageError(e.what());
    }
    if (const std::string why = tree::missing_hierarchy(tree); !why.empty()) throw StageError(why);
    auto texture = [&](const std::string& name, const char* what) {
      mesh::Texture t{name, ""};
      if (name.empty()) return t;
      const ArtifactFile* f = in.file(name);
      if (!f)
        throw StageError(sylt->path.string() + ": the tree's " + what + " texture '" + name +
                         "' is not a file of input '" + in.node + "'");
      t.bytes = ctx.read_input(*f);
      return t;
    };
    const mesh::Texture bark = texture(tree.materials.bark_texture, "bark");
    const mesh::Texture leaves = texture(tree.materials.leaf_texture, "leaf");

    // 2. Mesh (pure core).
    mesh::MeshOptions o;
    o.max_level = static_cast<int>(ctx.integer("max_level"));
    o.subdivision = static_cast<int>(ctx.integer("subdivision"));
    o.open_base = ctx.boolean("open_base");
    o.foliage = ctx.boolean("foliage");
    o.mesh_card_twigs = ctx.boolean("mesh_card_twigs");
    o.min_radius = ctx.real("min_radius_m");
    o.ring_tolerance = ctx.real("ring_tolerance");
    o.smooth_radius = ctx.real("smooth_radius");
    o.bark_repeat = static_cast<int>(ctx.integer("bark_repeat"));
    o.subdivider =
        ctx.string("subdivider") == "openmesh" ? mesh::Subdivider::kOpenMesh : mesh::Subdivider::kNative;
    o.count_self_intersections = ctx.boolean("self_intersections");
    gltf::Scene scene = ctx.boolean("keep_source")
                            ? source_model(tree, sylt->path.string(), ctx)
                            : remeshed(tree, o, bark, leaves, sylt->path.string(), ctx);
    write(ctx, scene);
  }

 private:
  // The sylva metadata of the GLB (asset.extras.sylva). The node name is deliberately absent: it
  // is not part of the action key, so two nodes with the same inputs share one cached output.
  nlohmann::json metadata(const tree::Tree& tree, const StageContext& ctx) const {
    nlohmann::json sylva = {
        {"stage", info_.name},
        {"stage_version", info_.version},
        {"source", tree.name},
        {"parameters", nlohmann::json::parse(Value(ctx.params()).canonical())},
    };
    if (!tree.source.empty())
      sylva["imported_model"] = ctx.boolean("keep_source")
                                    ? "the imported model itself (keep_source)"
                                    : "re-meshed from the skeleton the hierarchy stage reconstructed; "
                                      "keep_source: true writes the imported model itself";
    return sylva;
  }

  // keep_source: the imported model as the file had it (libs/sourcegltf).
  gltf::Scene source_model(const tree::Tree& tree, const std::string& sylt, const StageContext& ctx) const {
    if (tree.source.empty())
      throw StageError(sylt + ": keep_source is set, but tree '" + tree.name +
                       "' is not an imported mesh (it has no source geometry)");
    gltf::Scene scene = sourcegltf::source_scene(tree.source, "tree");
    scene.extras = {{"sylva", metadata(tree, ctx)}};
    return scene;
  }

  gltf::Scene remeshed(const tree::Tree& tree, const mesh::MeshOptions& o, const mesh::Texture& bark,
                       const mesh::Texture& leaves, const std::string& sylt, const StageContext& ctx) const {
    mesh::TreeMesh m;
    gltf::Scene scene;
    try {
      m = mesh::mesh_tree(tree, o);
      ctx.check_cancelled();
      nlohmann::json sylva = metadata(tree, ctx);
      sylva["statistics"] = mesh::stats_json(m.stats);
      scene = mesh::make_scene(m, tree, bark, leaves, sylva);
    } catch (const mesh::MeshError& e) {
      throw StageError(sylt + ": " + e.what());
    }
    return scene;
  }

  // 3. Write.
  static void write(StageContext& ctx, const gltf::Scene& scene) {
    gltf::WriteOptions w;
    w.format = ctx.string("format") == "gltf" ? gltf::FileFormat::kGltf : gltf::FileFormat::kGlb;
    w.draco.enabled = ctx.boolean("draco");
    w.draco.position_bits = static_cast<int>(ctx.integer("draco_position_bits"));
    w.draco.normal_bits = static_cast<int>(ctx.integer("draco_normal_bits"));
    w.draco.texcoord_bits = static_cast<int>(ctx.integer("draco_texcoord_bits"));
    w.draco.generic_bits = static_cast<int>(ctx.integer("draco_generic_bits"));
    w.draco.compression_level = static_cast<int>(ctx.integer("draco_level"));
    try {
      // Streamed (hashed while written): the file is never held in memory whole.
      auto out = ctx.open_output(std::string("tree") + gltf::extension(w.format));
      gltf::encode_to(scene, out->stream(), w);
      out->close();
    } catch (const gltf::GltfError& e) {
      throw StageError(std::string("cannot write the glTF file: ") + e.what());
    }
  }

  StageInfo info_;
};

}  // namespace

std::unique_ptr<Stage> make_mesh_stage() { return std::make_unique<MeshStage>(); }

}  // namespace sylva
