#include "app/inspect_command.h"

#include <memory>

#include "libs/tree/stats.h"
#include "libs/tree/sylt_format.h"

namespace sylva {
namespace {

class InspectCommand final : public CliCommand {
 public:
  CLI::App* add_to(CLI::App& app) override {
    auto* sub = app.add_subcommand("inspect", "print statistics of a tree file (.sylt)");
    sub->add_option("file", file_, "tree file")->required();
    sub->add_flag("--json", json_, "print JSON instead of text");
    return sub;
  }
  int run(CommandContext& ctx) override {
    const CliIo& io = ctx.io;
    try {
      const tree::Tree t = tree::read_sylt(file_);
      const auto stats = tree::compute_stats(t);
      std::string text = json_ ? tree::format_stats_json(stats) : tree::format_stats(stats);
      if (text.empty() || text.back() != '\n') text += '\n';
      std::fputs(text.c_str(), io.out);
      return kExitOk;
    } catch (const std::exception& e) {
      std::fprintf(io.err, "error: %s\n", e.what());
      return kExitBuildFailed;
    }
  }

 private:
  std::string file_;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<CliCommand> make_inspect_command() { return std::make_unique<InspectCommand>(); }

}  // namespace sylva
