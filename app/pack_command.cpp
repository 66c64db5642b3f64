#include "app/pack_command.h"

#include <memory>
#include <nlohmann/json.hpp>

#include "libs/pack/manifest.h"

namespace sylva {
namespace {

class PackCommand final : public CliCommand {
 public:
  CLI::App* add_to(CLI::App& app) override {
    auto* pack = app.add_subcommand("pack", "asset packs (stage `pack`)");
    pack->require_subcommand(1);
    auto* diff =
        pack->add_subcommand("diff", "list the files two pack manifests differ in: added, changed, removed");
    diff->add_option("old", old_, "the older pack/manifest.json")->required();
    diff->add_option("new", new_, "the newer pack/manifest.json")->required();
    diff->add_flag("--json", json_, "print {\"added\": [...], \"changed\": [...], \"removed\": [...]}");
    return pack;
  }
  int run(CommandContext& ctx) override {
    const CliIo& io = ctx.io;
    try {
      const pack::ManifestDiff d = pack::diff_manifests(pack::read_manifest(old_), pack::read_manifest(new_));
      if (json_) {
        const nlohmann::json j = {{"added", d.added}, {"changed", d.changed}, {"removed", d.removed}};
        std::fprintf(io.out, "%s\n", j.dump(2).c_str());
        return kExitOk;
      }
      for (const auto& p : d.added) std::fprintf(io.out, "added   %s\n", p.c_str());
      for (const auto& p : d.changed) std::fprintf(io.out, "changed %s\n", p.c_str());
      for (const auto& p : d.removed) std::fprintf(io.out, "removed %s\n", p.c_str());
      std::fprintf(io.out, "%zu added, %zu changed, %zu removed\n", d.added.size(), d.changed.size(),
                   d.removed.size());
      return kExitOk;
    } catch (const pack::ManifestError& e) {
      std::fprintf(io.err, "error: %s\n", e.what());
      return kExitBuildFailed;
    }
  }

 private:
  std::string old_, new_;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<CliCommand> make_pack_command() { return std::make_unique<PackCommand>(); }

}  // namespace sylva
