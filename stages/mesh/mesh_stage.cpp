// The adapter of stage `mesh`: declares the parameters, reads the upstream tree artifact
// (tree.sylt and the textures it names), runs the core (tree_mesh.h) and writes one glTF file
// through libs/gltf. Seed: Nystad 2010 §4.3 and §5.3 (the core says which part is where).
#include "stages/mesh/mesh_stage.h"

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "libs/gltf/writer.h"
#include "libs/tree/sylt_format.h"
#include "stages/mesh/tree_mesh.h"

namespace sylva {

namespace {

// 2: junction collapse, insets, windowed ring frames, ring merging. 3: libs/gltf writes no
// tangents without a normal map; colours from libs/tree/default_colors.h. 4: cards (atlas cells,
// card-drawn twigs), no tangents computed, bark tint, LAI statistics.
constexpr int kVersion = 4;

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw StageError(path.string() + ": cannot open the file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw StageError(path.string() + ": cannot read the file");
  return std::move(ss).str();
}

class MeshStage final : public Stage {
 public:
  MeshStage() {
    info_.name = "mesh";
    info_.version = kVersion;
    info_.summary = "tree -> GLB: one connected quad mesh with box joints (Nystad), Catmull-Clark, leaf cards, needles";
    info_.inputs = InputSpec{{"tree"}, 1, 1, "one tree (generate or import): tree.sylt and the textures it names"};
    info_.output_type = "mesh";
    info_.params = {
        Param::integer("max_level", -1).range(-1, 16)
            .describe("highest branch level meshed (trunk 0); -1 = every level"),
        Param::integer("subdivision", 1).range(0, 3).describe("Catmull-Clark levels (each multiplies the quads by 4)"),
        Param::boolean("open_base", false).describe("leave the trunk base open (default: closed)"),
        Param::boolean("foliage", true).describe("leaf quads or cards (alpha-masked, double-sided) and needles"),
        Param::boolean("mesh_card_twigs", false)
            .describe("also mesh the twigs that twig/shoot cards draw (default: the cards draw them)"),
        Param::real("min_radius_m", 0.001).range(1e-5, 1)
            .describe("thinner skeleton nodes (tapered tips reach 0) are meshed at this radius (m)"),
        Param::integer("bark_repeat", 1).range(1, 16).describe("bark texture repeats around a branch"),
        Param::choice("subdivider", {"native", "openmesh"}, "native")
            .describe("Catmull-Clark implementation: native (fast) or OpenMesh's CatmullClarkT (reference)"),
        Param::choice("format", {"glb", "gltf"}, "glb").describe("glb, or a self-contained .gltf (base64 buffer)"),
        Param::boolean("draco", false).describe("KHR_draco_mesh_compression for the triangle primitives"),
        Param::integer("draco_position_bits", 14).range(8, 30).describe("Draco quantisation of positions"),
        Param::integer("draco_normal_bits", 10).range(4, 30).describe("Draco quantisation of normals"),
        Param::integer("draco_texcoord_bits", 12).range(4, 30).describe("Draco quantisation of uvs"),
        Param::integer("draco_generic_bits", 12).range(4, 30).describe("Draco quantisation of tangents"),
        Param::integer("draco_level", 7).range(0, 10).describe("Draco compression level (0 fastest, 10 smallest)"),
        Param::boolean("self_intersections", false)
            .describe("count self-intersecting triangle pairs of the bark (CGAL) into the statistics; slow"),
    };
  }

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    // 1. Read the tree and the textures it names from the one input artifact.
    const InputArtifact& in = ctx.inputs().front();
    const ArtifactFile* sylt = in.file("tree.sylt");
    if (!sylt) throw StageError("input '" + in.node + "' has no tree.sylt");
    tree::Tree tree;
    try {
      tree = tree::read_sylt(sylt->path);
    } catch (const tree::TreeFormatError& e) {
      throw StageError(e.what());
    }
    auto texture = [&](const std::string& name, const char* what) {
      mesh::Texture t{name, ""};
      if (name.empty()) return t;
      const ArtifactFile* f = in.file(name);
      if (!f)
        throw StageError(sylt->path.string() + ": the tree's " + what + " texture '" + name + "' is not a file of input '" +
                         in.node + "'");
      t.bytes = read_bytes(f->path);
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
    o.bark_repeat = static_cast<int>(ctx.integer("bark_repeat"));
    o.subdivider = ctx.string("subdivider") == "openmesh" ? mesh::Subdivider::kOpenMesh : mesh::Subdivider::kNative;
    o.count_self_intersections = ctx.boolean("self_intersections");
    mesh::TreeMesh m;
    gltf::Scene scene;
    try {
      m = mesh::mesh_tree(tree, o);
      ctx.check_cancelled();
      // The node name is deliberately absent: it is not part of the action key, so two nodes
      // with the same inputs share one cached output.
      const nlohmann::json sylva = {
          {"stage", info_.name},
          {"stage_version", kVersion},
          {"source", tree.name},
          {"parameters", nlohmann::json::parse(Value(ctx.params()).canonical())},
          {"statistics", mesh::stats_json(m.stats)},
      };
      scene = mesh::make_scene(m, tree, bark, leaves, sylva);
    } catch (const mesh::MeshError& e) {
      throw StageError(sylt->path.string() + ": " + e.what());
    }

    // 3. Write.
    gltf::WriteOptions w;
    w.format = ctx.string("format") == "gltf" ? gltf::FileFormat::kGltf : gltf::FileFormat::kGlb;
    w.draco.enabled = ctx.boolean("draco");
    w.draco.position_bits = static_cast<int>(ctx.integer("draco_position_bits"));
    w.draco.normal_bits = static_cast<int>(ctx.integer("draco_normal_bits"));
    w.draco.texcoord_bits = static_cast<int>(ctx.integer("draco_texcoord_bits"));
    w.draco.generic_bits = static_cast<int>(ctx.integer("draco_generic_bits"));
    w.draco.compression_level = static_cast<int>(ctx.integer("draco_level"));
    try {
      ctx.write_output(std::string("tree") + gltf::extension(w.format), gltf::encode(scene, w));
    } catch (const gltf::GltfError& e) {
      throw StageError(std::string("cannot write the glTF file: ") + e.what());
    }
  }

 private:
  StageInfo info_;
};

}  // namespace

std::unique_ptr<Stage> make_mesh_stage() { return std::make_unique<MeshStage>(); }

}  // namespace sylva
