// The adapter of stage `pack`: names each input by `species`, reads its lod files (libs/gltf
// reader), runs the core and writes the files and manifest.json (libs/pack).
#include "stages/pack/pack_stage.h"

#include <regex>
#include <set>

#include "libs/gltf/reader.h"
#include "libs/pack/manifest.h"
#include "stages/pack/pack_core.h"
#include "stages/pack/pack_info.h"

namespace sylva {

namespace {

class PackStage : public Stage {
 public:
  PackStage() : info_(pack_stage_info()) {}
  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    const Value::List& names = ctx.param("species").as_list();
    const auto& inputs = ctx.inputs();
    if (names.size() != inputs.size())
      throw StageError("`species` names " + std::to_string(names.size()) + " species but the node has " +
                       std::to_string(inputs.size()) + " inputs (one name per input, in `needs` order)");
    pack::PackOptions options;
    const std::string& c = ctx.string("compression");
    options.compression = c == "none"    ? pack::Compression::kNone
                          : c == "draco" ? pack::Compression::kDraco
                                         : pack::Compression::kMeshopt;
    options.optimize = ctx.boolean("optimize");
    options.quantize = ctx.boolean("quantize");
    options.position_error = ctx.real("position_error");
    options.normal_bits = static_cast<int>(ctx.integer("normal_bits"));
    options.texcoord_bits = static_cast<int>(ctx.integer("texcoord_bits"));

    static const std::regex kName("[a-z0-9_-]+");
    std::set<std::string> seen;
    pack::Manifest manifest;
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      const std::string& species = names[k].as_string();
      if (!std::regex_match(species, kName))
        throw StageError("`species` entry '" + species.substr(0, 64) + "' is not a plain name ([a-z0-9_-]+)");
      if (!seen.insert(species).second) throw StageError("`species` names '" + species + "' twice");
      const InputArtifact& in = inputs[k];
      ctx.check_cancelled();
      const std::vector<pack::PackedFile> files = pack::pack_species(read_species(in, species), options);
      ctx.check_cancelled();
      pack::SpeciesEntry entry{species, files.front().name, files.back().name, {}};
      for (std::size_t f = 1; f + 1 < files.size(); ++f) entry.levels.push_back(files[f].name);
      for (const pack::PackedFile& f : files) {
        pack::Producer producer{info_.name, info_.version, {}};
        for (const std::string& name : f.inputs)
          producer.inputs.emplace(in.type + "/" + name, in.file(name)->digest);
        manifest.files.push_back(pack::describe_file(f.name, f.bytes, std::move(producer)));
        ctx.write_output(f.name, f.bytes);
      }
      manifest.species.push_back(std::move(entry));
    }
    ctx.write_output("manifest.json", pack::write_manifest(manifest));
  }

 private:
  // The chain and its levels as the lod stage wrote them (lod.gltf, lod<i>.gltf with their .bin
  // and texture files beside them), and the input files each output is made from.
  static pack::SpeciesInput read_species(const InputArtifact& in, const std::string& species) {
    pack::SpeciesInput s;
    s.species = species;
    const ArtifactFile* chain = in.file("lod.gltf");
    if (!chain) throw StageError("input '" + in.node + "' has no lod.gltf (is it a lod node?)");
    std::vector<std::string> shared;  // textures: every file of the chain and of each level uses them
    for (const ArtifactFile* f : in.files_with_suffix(".png")) shared.push_back(f->name);
    try {
      s.chain = gltf::read_scene(chain->path);
      s.chain_inputs = {"lod.gltf"};
      for (std::size_t i = 0;; ++i) {
        const std::string stem = "lod" + std::to_string(i);
        const ArtifactFile* level = in.file(stem + ".gltf");
        if (!level) break;
        s.levels.push_back(gltf::read_scene(level->path));
        std::vector<std::string> used = {stem + ".gltf"};
        if (in.file(stem + ".bin")) {
          used.push_back(stem + ".bin");
          s.chain_inputs.push_back(stem + ".bin");
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

  StageInfo info_;
};

}  // namespace

std::unique_ptr<Stage> make_pack_stage() { return std::make_unique<PackStage>(); }

}  // namespace sylva
