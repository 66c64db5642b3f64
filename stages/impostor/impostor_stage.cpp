// The thin adapter of stage `impostor`: declares the parameters, reads the input artifact (a mesh's
// tree.glb, or the level of a lod chain that source.h chooses), runs the core (bake.h) on the
// shared headless renderer and writes the four outputs.
#include "stages/impostor/impostor_stage.h"

#include <algorithm>
#include <thread>

#include "libs/gltf/writer.h"
#include "libs/image/image_io.h"
#include "libs/lodmodel/lod_model.h"
#include "libs/render/gltf_scene.h"
#include "stages/impostor/atlas_png.h"
#include "stages/impostor/impostor_info.h"
#include "stages/impostor/source.h"

namespace sylva {

namespace {

render::Scene load(const StageContext& ctx, const ArtifactFile& f) {
  try {
    return render::load_gltf_scene(f.path, ctx.files());
  } catch (const render::SceneLoadError& e) {
    throw StageError(e.what());
  }
}

// The mesh artifact's one glTF file.
const ArtifactFile& mesh_file(const InputArtifact& in) {
  std::vector<const ArtifactFile*> files = in.files_with_suffix(".glb");
  for (const ArtifactFile* f : in.files_with_suffix(".gltf")) files.push_back(f);
  if (files.size() != 1)
    throw StageError("input '" + in.node + "' (mesh) must hold exactly one .glb or .gltf file, has " +
                     std::to_string(files.size()));
  return *files.front();
}

class ImpostorStage final : public Stage {
 public:
  explicit ImpostorStage(std::function<render::ImpostorRenderer&()> renderer)
      : renderer_(std::move(renderer)) {
    info_ = impostor_stage_info();
  }

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    const impostor::BakeParams params = [&] {
      try {
        return bake_params_from(ctx.params());
      } catch (const std::invalid_argument& e) {
        throw StageError(e.what());
      }
    }();
    // 1. The source: the mesh, or the coarsest LOD level within one atlas texel.
    const InputArtifact& in = ctx.inputs()[0];
    impostor::SourceDesc src;
    render::Scene scene;
    if (in.type == "lod") {
      const ArtifactFile* summary = in.file(lodchain::kSummaryFile);
      if (!summary) throw StageError("input '" + in.node + "' (lod) has no lod.json");
      std::vector<impostor::LodLevelRef> levels;
      try {
        levels = impostor::lod_level_refs(
            lodchain::parse_lod_chain(ctx.read_input(*summary), summary->path.string()));
      } catch (const lodchain::LodChainFormatError& e) {
        throw StageError(e.what());
      }
      auto level_file = [&](std::size_t i) -> const ArtifactFile& {
        const ArtifactFile* f = in.file(levels[i].file);
        if (!f)
          throw StageError("input '" + in.node + "': lod.json lists " + levels[i].file +
                           ", which the artifact lacks");
        return *f;
      };
      // The coarsest level within one atlas texel (source.h).
      try {
        src = impostor::choose_source(levels, load(ctx, level_file(levels.size() - 1)), params.layout);
      } catch (const std::invalid_argument& e) {
        throw StageError(e.what());
      }
      scene = load(ctx, level_file(std::size_t(src.level)));
    } else {
      const ArtifactFile& f = mesh_file(in);
      scene = load(ctx, f);
      src.type = "mesh";
      src.file = f.name;
    }
    ctx.check_cancelled();
    // 2. Bake (the core).
    impostor::BakeOutput out;
    try {
      out = impostor::bake_impostor(renderer_(), scene, params, src);
    } catch (const std::invalid_argument& e) {
      throw StageError(e.what());
    } catch (const render::RenderError& e) {
      throw StageError(e.what());
    } catch (const gltf::GltfError& e) {
      throw StageError(std::string("writing impostor.glb: ") + e.what());
    }
    ctx.check_cancelled();
    // 3. Write.
    try {
      // Both maps at once, at zlib level 3 (atlas_png.h).
      const impostor::AtlasPngs pngs = impostor::encode_atlas_pngs(out.color, out.normal_depth);
      ctx.write_output(out.info.color_map,
                       std::string_view(reinterpret_cast<const char*>(pngs.color.data()), pngs.color.size()));
      ctx.write_output(out.info.normal_depth_map,
                       std::string_view(reinterpret_cast<const char*>(pngs.normal_depth.data()),
                                        pngs.normal_depth.size()));
    } catch (const image::ImageError& e) {
      throw StageError(e.what());
    }
    ctx.write_output(impostor::kImpostorGlbFile, out.glb);
    ctx.write_output(impostor::kImpostorJsonFile, impostor::write_impostor_json(out.info));
  }

 private:
  StageInfo info_;
  std::function<render::ImpostorRenderer&()> renderer_;
};

}  // namespace

impostor::BakeParams bake_params_from(const Value::Object& params) {
  auto at = [&](const char* name) -> const Value& {
    auto it = params.find(name);
    if (it == params.end())
      throw std::invalid_argument(std::string("impostor parameters: '") + name + "' is missing");
    return it->second;
  };
  impostor::BakeParams p;
  const std::string& kind = at("kind").as_string();
  p.layout.kind = kind == "octahedral"   ? impostor::Kind::kOctahedral
                  : kind == "billboards" ? impostor::Kind::kBillboards
                                         : impostor::Kind::kHemiOctahedral;
  p.layout.frames_per_side = int(at("frames").as_int());
  p.layout.frame_px = int(at("frame_px").as_int());
  p.layout.mip_levels = int(at("mip_levels").as_int());
  p.layout.cards = int(at("cards").as_int());
  p.layout.top_card = at("top_card").as_bool();
  p.cutout_vertices = int(at("cutout_vertices").as_int());
  p.msaa = int(at("msaa").as_int());
  // Not a parameter: the thread count changes no byte (impostor_renderer.h), so it stays out of
  // the action key.
  p.threads = int(std::clamp(std::thread::hardware_concurrency(), 1u, 4u));
  p.glb_alpha.blend = at("glb_alpha").as_string() == "blend";
  p.glb_alpha.cutoff = float(at("alpha_cutoff").as_real());
  const Value::Object& cam = at("camera").as_object();
  p.camera = lodmodel::camera_from_degrees(cam.at("fov_y_deg").as_real(), int(cam.at("height_px").as_int()));
  p.pixel_error = at("pixel_error").as_real();
  p.switch_distance_m = at("switch_distance_m").as_real();
  return p;
}

std::unique_ptr<Stage> make_impostor_stage(std::function<render::ImpostorRenderer&()> renderer) {
  return std::make_unique<ImpostorStage>(std::move(renderer));
}

std::unique_ptr<Stage> make_impostor_stage() {
  return make_impostor_stage(
      []() -> render::ImpostorRenderer& { return render::shared_impostor_renderer(); });
}

}  // namespace sylva
