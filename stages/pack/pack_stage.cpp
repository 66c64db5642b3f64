// The adapter of stage `pack`: names each lod input (and the impostor input beside it) by
// `species`, reads the lod files and impostor.glb (libs/gltf reader) and impostor.json
// (libs/impostor), runs the core — with `measure`, through a RenderedLevelMeter over the lod
// input's full.glb and lod.json's camera (level_meter.h) —, compresses or copies each forest
// input's files, merges other pack nodes' outputs (their files checked against their manifests),
// and writes manifest.json (libs/pack).
#include "stages/pack/pack_stage.h"

#include <fnmatch.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <set>

#include "libs/forest/instances.h"
#include "libs/gltf/meshopt_files.h"
#include "libs/gltf/reader.h"
#include "libs/gltf/writer.h"
#include "libs/impostor/impostor_json.h"
#include "libs/lodchain/lod_chain.h"
#include "libs/lodmodel/lod_model.h"
#include "libs/pack/manifest.h"
#include "libs/render/gltf_scene.h"
#include "libs/render/shared_renderer.h"
#include "pipeline/digest.h"
#include "stages/pack/level_meter.h"
#include "stages/pack/pack_core.h"
#include "stages/pack/pack_info.h"

namespace sylva {

namespace {

class PackStage : public Stage {
 public:
  explicit PackStage(std::function<render::Renderer&()> renderer)
      : info_(pack_stage_info()), renderer_(std::move(renderer)) {}
  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    const Value::List& names = ctx.param("species").as_list();
    const Value::List& forest_names = ctx.param("forests").as_list();
    const Inputs in = group_inputs(ctx, names.size(), forest_names.size());
    const pack::PackOptions options = pack_options(ctx);
    const std::optional<check::ViewCheckOptions> view_options = measure_options(ctx);

    std::set<std::string> seen, forests_seen;    // species and forest names
    std::map<std::string, std::string> written;  // output name -> what wrote it (collisions)
    auto claim = [&](const std::string& name, const std::string& what) {
      const auto [it, fresh] = written.emplace(name, what);
      if (!fresh)
        throw StageError("two files of the pack are named '" + name + "': " + it->second + " and " + what);
    };
    pack::Manifest manifest;
    for (std::size_t k = 0; k < in.lods.size(); ++k) {
      const std::string& species = names[k].as_string();
      check_name("species", species, seen);
      const InputArtifact* imp = in.impostors.empty() ? nullptr : in.impostors[k];
      pack_one_species(ctx, *in.lods[k], imp, species, options, view_options, claim, manifest);
    }
    for (std::size_t k = 0; k < in.forests.size(); ++k) {
      const std::string& name = forest_names[k].as_string();
      check_name("forests", name, forests_seen);
      manifest.forests.push_back(copy_forest(ctx, *in.forests[k], name,
                                             ctx.string("forest_compression") == "meshopt", claim, manifest));
    }
    for (const InputArtifact* p : in.packs) merge_pack(ctx, *p, claim, seen, forests_seen, manifest);
    ctx.write_output(pack::kManifestFile, pack::write_manifest(manifest));
  }

 private:
  // The node's inputs by type; lod inputs are every input of another type.
  struct Inputs {
    std::vector<const InputArtifact*> lods, impostors, forests, packs;
  };

  // The inputs grouped by type, checked against the `species` (`species` names) and `forests`
  // (`forests` names) lists: one name per lod and per forest input, and no impostor input or one
  // per lod input.
  static Inputs group_inputs(const StageContext& ctx, std::size_t species, std::size_t forest_names) {
    Inputs g;
    for (const InputArtifact& in : ctx.inputs())
      (in.type == "impostor" ? g.impostors
       : in.type == "forest" ? g.forests
       : in.type == "pack"   ? g.packs
                             : g.lods)
          .push_back(&in);
    if (species != g.lods.size())
      throw StageError("`species` names " + std::to_string(species) + " species but the node has " +
                       std::to_string(g.lods.size()) +
                       " lod inputs (one name per lod input, in `needs` order)");
    if (!g.impostors.empty() && g.impostors.size() != g.lods.size())
      throw StageError(
          "the node has " + std::to_string(g.impostors.size()) + " impostor inputs for " +
          std::to_string(g.lods.size()) +
          " lod inputs (none, or one per species: the i-th impostor input ends species[i]'s chain)");
    if (forest_names != g.forests.size())
      throw StageError("`forests` names " + std::to_string(forest_names) + " forests but the node has " +
                       std::to_string(g.forests.size()) +
                       " forest inputs (one name per forest input, in `needs` order)");
    return g;
  }

  // The core's options from the node's parameters.
  static pack::PackOptions pack_options(StageContext& ctx) {
    pack::PackOptions options;
    const std::string& c = ctx.string("compression");
    options.compression = c == "none"    ? pack::Compression::kNone
                          : c == "draco" ? pack::Compression::kDraco
                                         : pack::Compression::kMeshopt;
    options.optimize = ctx.boolean("optimize");
    options.quantize = ctx.boolean("quantize");
    options.position_error = ctx.real("position_error");
    options.position_error_max = ctx.real("position_error_max");
    if (options.position_error_max < options.position_error)
      throw StageError("`position_error_max` (" + std::to_string(options.position_error_max) +
                       ") is below `position_error` (" + std::to_string(options.position_error) +
                       "): it bounds the 16-bit grid of a level whose position_error grid would need "
                       "more than 16 bits");
    options.normal_bits = static_cast<int>(ctx.integer("normal_bits"));
    options.texcoord_bits = static_cast<int>(ctx.integer("texcoord_bits"));
    options.min_saving = ctx.real("min_saving");
    options.position_bits_min = static_cast<int>(ctx.integer("position_bits_min"));
    options.nearer_line_coverage = ctx.boolean("nearer_line_coverage");
    return options;
  }

  // With `measure`, the views of the measured level choice (lodcheck's, with the node's
  // azimuths, supersampling and thresholds); without, nullopt (the error model's choice).
  static std::optional<check::ViewCheckOptions> measure_options(StageContext& ctx) {
    if (!ctx.boolean("measure")) return std::nullopt;
    check::ViewCheckOptions view_options;
    view_options.azimuths_deg.clear();
    // The schema holds the azimuths to [-360, 360] and at least one (pack_info.cpp).
    for (const Value& a : ctx.param("measure_azimuths_deg").as_list())
      view_options.azimuths_deg.push_back(a.as_real());
    view_options.supersample = static_cast<int>(ctx.integer("measure_supersample"));
    view_options.max_failing_fraction = ctx.real("measure_max_failing_fraction");
    view_options.max_coverage_error = ctx.real("measure_max_coverage_error");
    return view_options;
  }

  // A `species` or `forests` entry: a plain name ([a-z0-9_-]+), not named before (`seen`).
  static void check_name(const std::string& list, const std::string& name, std::set<std::string>& seen) {
    static const std::regex kName("[a-z0-9_-]+");
    if (!std::regex_match(name, kName))
      throw StageError("`" + list + "` entry '" + name.substr(0, 64) + "' is not a plain name ([a-z0-9_-]+)");
    if (!seen.insert(name).second) throw StageError("`" + list + "` names '" + name + "' twice");
  }

  // One species: its lod input `in` (and impostor input `imp`, when given) packed by the core,
  // each file written and listed in the manifest with the input files it is made from, and the
  // species' entry.
  template <class Claim>
  void pack_one_species(StageContext& ctx, const InputArtifact& in, const InputArtifact* imp,
                        const std::string& species, const pack::PackOptions& options,
                        const std::optional<check::ViewCheckOptions>& view_options, Claim& claim,
                        pack::Manifest& manifest) const {
    ctx.check_cancelled();
    pack::SpeciesInput s = read_species(ctx, in, species);
    if (imp) s.impostor = read_impostor(ctx, *imp);
    std::vector<pack::PackedFile> files;
    pack::LodDescription described;
    const std::string which = "species '" + species + "' (input '" + in.node + "'" +
                              (imp ? ", impostor '" + imp->node + "'" : std::string()) + "): ";
    std::optional<pack::RenderedLevelMeter> meter;
    if (view_options) meter.emplace(make_meter(ctx, in, *view_options));
    try {
      files = pack::pack_species(s, options, &described, meter ? &*meter : nullptr);
    } catch (const std::invalid_argument& e) {
      throw StageError(which + e.what());
    } catch (const Cancelled&) {
      throw;
    } catch (const std::runtime_error& e) {  // the measurement: a file the loader refuses, rendering
      throw StageError(which + "measuring its levels: " + e.what());
    }
    ctx.check_cancelled();
    pack::SpeciesEntry entry{species, files.front().name, files.back().name, std::move(described.levels), {}};
    if (imp && entry.levels.back().kind == "impostor") entry.impostor = entry.levels.back().file;
    for (const pack::PackedFile& f : files) {
      claim(f.name, "species '" + species + "'");
      pack::Producer producer{info_.name, info_.version, {}};
      for (const std::string& name : f.inputs) {
        const InputArtifact& from = name.rfind("impostor/", 0) == 0 ? *imp : in;
        const std::string file = name.rfind("impostor/", 0) == 0 ? name.substr(9) : name;
        producer.inputs.emplace(from.type + "/" + file, from.file(file)->digest);
      }
      manifest.files.push_back(pack::describe_file(f.name, f.bytes, std::move(producer)));
      ctx.write_output(f.name, f.bytes);
    }
    manifest.species.push_back(std::move(entry));
  }

  // The measured level choice's meter for lod input `in`: its full-detail model (full.glb), the
  // camera and pixel error its chain is for (lod.json), the process's headless renderer.
  pack::RenderedLevelMeter make_meter(StageContext& ctx, const InputArtifact& in,
                                      check::ViewCheckOptions view_options) const {
    const ArtifactFile* full = in.file(lodchain::kFullDetailFile);
    if (!full)
      throw StageError("input '" + in.node +
                       "' has no full.glb, the full-detail model the measured level choice judges against "
                       "(a lod node of stage version 10 or later writes it; or set `measure: false`)");
    const ArtifactFile* summary = in.file(lodchain::kSummaryFile);
    if (!summary) throw StageError("input '" + in.node + "' has no lod.json (is it a lod node?)");
    lodchain::LodChain chain;  // its camera in (0, 180) degrees and >= 1 px, its delta > 0
    try {
      chain = lodchain::parse_lod_chain(ctx.read_input(*summary), summary->path.string());
    } catch (const lodchain::LodChainFormatError& e) {
      throw StageError("input '" + in.node + "': " + e.what());
    }
    const lodmodel::Camera camera = chain.camera();
    // An edge moved by delta pixels changes a pixel's coverage by at most delta (as lodcheck).
    view_options.pixel_threshold = std::min(1.0, chain.pixel_error_px);
    render::Scene scene;
    try {
      scene = render::load_gltf_scene_from_memory(ctx.read_input(*full), full->path.string(),
                                                  full->path.parent_path());
    } catch (const std::exception& e) {
      throw StageError("input '" + in.node + "': " + e.what());
    }
    render::Renderer* renderer = nullptr;
    try {
      renderer = &renderer_();
    } catch (const render::RenderError& e) {
      throw StageError(std::string("measuring the levels needs the headless renderer: ") + e.what());
    }
    pack::RenderedLevelMeter meter(*renderer, std::move(scene), camera, view_options);
    meter.check_cancelled = [&ctx] { ctx.check_cancelled(); };
    return meter;
  }

  // The chain and its levels as the lod stage wrote them (lod.gltf, lod<i>.gltf with their .bin
  // and texture files beside them), and the input files each output is made from.
  static pack::SpeciesInput read_species(const StageContext& ctx, const InputArtifact& in,
                                         const std::string& species) {
    pack::SpeciesInput s;
    s.species = species;
    const ArtifactFile* chain = in.file(lodchain::kChainFile);
    if (!chain) throw StageError("input '" + in.node + "' has no lod.gltf (is it a lod node?)");
    std::vector<std::string> shared;  // textures: every file of the chain and of each level uses them
    for (const char* suffix : {".png", ".jpg"})  // an imported tree's level 0 may carry JPEG images
      for (const ArtifactFile* f : in.files_with_suffix(suffix)) shared.push_back(f->name);
    try {
      s.chain = gltf::read_scene(chain->path, ctx.files());
      s.chain_inputs = {lodchain::kChainFile};
      for (std::size_t i = 0;; ++i) {
        const ArtifactFile* level = in.file(lodchain::level_file(i));
        if (!level) break;
        s.levels.push_back(gltf::read_scene(level->path, ctx.files()));
        std::vector<std::string> used = {lodchain::level_file(i)};
        if (in.file(lodchain::level_bin(i))) {
          used.push_back(lodchain::level_bin(i));
          s.chain_inputs.push_back(lodchain::level_bin(i));
        }
        used.insert(used.end(), shared.begin(), shared.end());
        s.level_inputs.push_back(std::move(used));
      }
    } catch (const gltf::ReadError& e) {
      throw StageError("input '" + in.node + "': " + e.what());
    }
    s.chain_inputs.insert(s.chain_inputs.end(), shared.begin(), shared.end());
    if (s.levels.empty()) throw StageError("input '" + in.node + "' has no lod0.gltf");
    return s;
  }

  // impostor.glb (the level every client draws) and impostor.json's error model (libs/impostor).
  // Input names carry the prefix "impostor/" so that the manifest names the right artifact.
  static pack::ImpostorLevelInput read_impostor(const StageContext& ctx, const InputArtifact& in) {
    const ArtifactFile* json = in.file(impostor::kImpostorJsonFile);
    const ArtifactFile* glb = in.file(impostor::kImpostorGlbFile);
    if (!json || !glb)
      throw StageError("input '" + in.node +
                       "' has no impostor.json and impostor.glb (is it an impostor node?)");
    pack::ImpostorLevelInput out;
    try {
      const impostor::ImpostorInfo info =
          impostor::parse_impostor_json(ctx.read_input(*json), json->path.string());
      out.kind = impostor::kind_name(info.kind);
      out.epsilon_m = info.error.epsilon_m();
      out.pixel_error_px = info.pixel_error_px;
      out.switch_distance_m = info.switch_distance_m;
      out.camera = info.camera;
    } catch (const impostor::ImpostorFormatError& e) {
      throw StageError("input '" + in.node + "': " + e.what());
    }
    if (!(out.switch_distance_m > 0) || !(out.epsilon_m > 0))
      throw StageError("input '" + in.node + "': impostor.json has no positive switch distance and epsilon");
    try {
      out.scene = gltf::read_scene(glb->path, ctx.files());
    } catch (const gltf::ReadError& e) {
      throw StageError("input '" + in.node + "': " + e.what());
    }
    out.inputs = {std::string("impostor/") + impostor::kImpostorJsonFile,
                  std::string("impostor/") + impostor::kImpostorGlbFile};
    return out;
  }

  // Every file of a forest artifact under its own name (its tiles name the species' level files
  // by those names); with `compress`, its .gltf files and the .bin buffers they name through
  // EXT_meshopt_compression (libs/gltf/meshopt_files.h: lossless, the same codecs as the
  // species' GLBs), every other file copied byte for byte. The manifest's forest entry lists them.
  template <class Claim>
  pack::ForestEntry copy_forest(StageContext& ctx, const InputArtifact& in, const std::string& name,
                                bool compress, Claim& claim, pack::Manifest& manifest) const {
    pack::ForestEntry e;
    e.name = name;
    if (!in.file(forest::kTilesetJson) || !in.file(forest::kInstancesJson))
      throw StageError("input '" + in.node +
                       "' has no tileset.json and instances.json (is it a forest node?)");
    e.tileset = forest::kTilesetJson;
    e.instances = forest::kInstancesJson;
    // The rewritten files, and for each the input files it is made from: a .gltf from itself and
    // the .bin files it names; a .bin from itself and the .gltf files naming it (their views set
    // its layout).
    gltf::GltfFileSet rewritten;
    std::map<std::string, std::set<std::string>> made_from;
    if (compress) {
      gltf::GltfFileSet set;
      for (const ArtifactFile& f : in.files) {
        const bool is_gltf = f.name.size() > 5 && f.name.ends_with(".gltf");
        if (!is_gltf && !f.name.ends_with(".bin")) continue;
        ctx.check_cancelled();
        (is_gltf ? set.gltf : set.bins)[f.name] = ctx.read_input(f);
      }
      for (const auto& [file, text] : set.gltf) {
        made_from[file].insert(file);
        const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
        if (!j.is_object() || !j.contains("buffers") || !j["buffers"].is_array()) continue;
        for (const auto& b : j["buffers"]) {
          if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string()) continue;
          const std::string uri = b["uri"].get<std::string>();
          if (!set.bins.count(uri)) continue;
          made_from[file].insert(uri);
          made_from[uri].insert({uri, file});
        }
      }
      try {
        rewritten = gltf::meshopt_compress_files(set);
      } catch (const gltf::GltfError& err) {
        throw StageError("input '" + in.node + "': " + err.what());
      }
      // Only files whose bytes changed are written anew.
      for (auto* map : {&rewritten.gltf, &rewritten.bins})
        for (auto it = map->begin(); it != map->end();)
          it = (map == &rewritten.gltf ? set.gltf : set.bins).at(it->first) == it->second ? map->erase(it)
                                                                                          : std::next(it);
    }
    for (const ArtifactFile& f : in.files) {
      ctx.check_cancelled();
      claim(f.name, "forest '" + name + "'");
      pack::FileEntry entry;
      const std::string* bytes = nullptr;
      if (const auto g = rewritten.gltf.find(f.name); g != rewritten.gltf.end()) bytes = &g->second;
      if (const auto b = rewritten.bins.find(f.name); b != rewritten.bins.end()) bytes = &b->second;
      if (bytes) {
        pack::Producer producer{info_.name, info_.version, {}};
        for (const std::string& from : made_from.at(f.name))
          producer.inputs.emplace(in.type + "/" + from, in.file(from)->digest);
        entry = pack::describe_file(f.name, *bytes, std::move(producer));
        ctx.write_output(f.name, *bytes);
      } else {
        ctx.link_output(f.name, f);  // the verified input file itself (a hard link)
        entry.path = f.name;
        entry.sha256 = f.digest;
        entry.size = f.size;
        entry.media_type = pack::media_type_for(f.name);
        entry.producer = {info_.name, info_.version, {{in.type + "/" + f.name, f.digest}}};
      }
      manifest.files.push_back(std::move(entry));
      e.files.push_back(f.name);
      if (fnmatch("tile_*_lod*.gltf", f.name.c_str(), 0) == 0) e.tiles.push_back(f.name);
    }
    return e;
  }

  // A pack input (another pack node's output) joins this pack: every file its manifest lists,
  // checked against the listed size and SHA-256 and written under its name with its manifest
  // entry unchanged (its producer is the node that made it), then its species and forests. One
  // pack node per species and per forest, merged by one more, keeps a rebuild's pack work
  // proportional to what changed (docs/stages/pack.md, "Merging packs").
  template <class Claim>
  void merge_pack(StageContext& ctx, const InputArtifact& in, Claim& claim, std::set<std::string>& species,
                  std::set<std::string>& forests, pack::Manifest& manifest) const {
    const ArtifactFile* listing = in.file(pack::kManifestFile);
    if (!listing) throw StageError("input '" + in.node + "' has no manifest.json (is it a pack node?)");
    pack::Manifest sub;
    try {
      sub = pack::parse_manifest(ctx.read_input(*listing), listing->path.string());
    } catch (const pack::ManifestError& e) {
      throw StageError("input '" + in.node + "': " + e.what());
    }
    if (sub.version != pack::kManifestVersion)
      throw StageError("input '" + in.node + "': its manifest is version " + std::to_string(sub.version) +
                       "; a pack merges only version " + std::to_string(pack::kManifestVersion) +
                       " manifests (rebuild that node)");
    std::set<std::string> listed;
    for (const pack::FileEntry& f : sub.files) listed.insert(f.path);
    for (const ArtifactFile& f : in.files)
      if (f.name != pack::kManifestFile && !listed.count(f.name))
        throw StageError("input '" + in.node + "' has '" + f.name + "', which its manifest does not list");
    for (pack::FileEntry& f : sub.files) {
      ctx.check_cancelled();
      const ArtifactFile* file = in.file(f.path);
      if (!file)
        throw StageError("input '" + in.node + "': its manifest lists '" + f.path +
                         "', which it does not have");
      // The engine verified the input file against its digest: compare that with the manifest's,
      // and pass the file on as it is (a hard link; nothing is read).
      if (file->size != f.size || file->digest != f.sha256)
        throw StageError("input '" + in.node + "': '" + f.path +
                         "' is not the file its manifest describes (size or SHA-256 differs)");
      claim(f.path, "pack '" + in.node + "'");
      ctx.link_output(f.path, *file);
      manifest.files.push_back(std::move(f));
    }
    for (pack::SpeciesEntry& e : sub.species) {
      if (!species.insert(e.name).second)
        throw StageError("species '" + e.name + "' comes twice: input '" + in.node + "' has it too");
      manifest.species.push_back(std::move(e));
    }
    for (pack::ForestEntry& e : sub.forests) {
      if (!forests.insert(e.name).second)
        throw StageError("forest '" + e.name + "' comes twice: input '" + in.node + "' has it too");
      manifest.forests.push_back(std::move(e));
    }
  }

  StageInfo info_;
  std::function<render::Renderer&()> renderer_;
};

}  // namespace

std::unique_ptr<Stage> make_pack_stage(std::function<render::Renderer&()> renderer) {
  if (!renderer) renderer = []() -> render::Renderer& { return render::shared_renderer(); };
  return std::make_unique<PackStage>(std::move(renderer));
}

}  // namespace sylva
