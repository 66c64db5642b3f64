// The base of the commands that check a recipe's built outputs outside the cache (`sylva verify`,
// `sylva lodcheck`, `sylva impostorcheck`). What they share is here, once; each command supplies
// only its stage, its own options, its per-node check and its report writing.
//
// Options (in this order in --help): `[RECIPE]` (default configs/default.yaml), `--node NODE`
// (repeatable), the command's mode options (add_mode_options), `-j,--jobs N`, `--report-dir DIR`,
// the command's own options (add_options), and `--no-images` when the spec gives it a help text.
//
// run() is one straight sequence, with the exit codes of docs/architecture.md:
//  1. load the recipe (ctx.fs; diagnostics, exit 2);
//  2. select the nodes (select(): by default those named by --node, in that order, or every node
//     of the spec's stage; a wrong name or no such node is one line and exit 2);
//  3. the command's own usage checks (check_usage(); exit 2);
//  4. the report root: --report-dir, else <out>/<recipe>/<spec.reports_dir>, refused (exit 2)
//     when the recipe has a node of that name;
//  5. build targets() through the engine and the cache (app/recipe_build.h; exit 1 when they do
//     not build);
//  6. prepare() (e.g. a renderer; "error: <why>" and exit 1 when it throws);
//  7. check_node() per selected node, into <report root>/<node>/; Ctrl-C or SIGTERM before a node
//     or inside one (check_node returns kExitInterrupted) ends the command with one line and 130;
//  8. exit 0 when every node's check returned kExitOk, else 1.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/recipe_build.h"
#include "app/report_dir.h"

namespace sylva {

// What names a check command and what its shared options say (help texts are the command's:
// `sylva <name> --help` prints them as given).
struct CheckCommandSpec {
  const char* name;             // the subcommand ("lodcheck"); messages say "sylva <name>"
  const char* stage;            // the stage whose nodes it checks by default ("lod")
  const char* doc_page;         // where adding such a node is documented ("docs/stages/lod.md")
  const char* reports_dir;      // the default report root's name under <out>/<recipe>/ ("lodcheck")
  const char* summary;          // the subcommand's one-line description
  const char* node_help;        // --node
  const char* jobs_help;        // -j,--jobs
  const char* report_dir_help;  // --report-dir
  const char* no_images_help;   // --no-images; nullptr: the command has no such option
};

class CheckCommand : public CliCommand {
 public:
  explicit CheckCommand(CheckCommandSpec spec) : spec_(spec) {}

  CLI::App* add_to(CLI::App& app) final;
  int run(CommandContext& ctx) final;

 protected:
  // Options that change what the command does, listed right after --node (verify: --update-refs).
  virtual void add_mode_options(CLI::App& /*sub*/) {}
  // The command's own options, listed after --report-dir.
  virtual void add_options(CLI::App& /*sub*/) {}
  // The nodes to check, in order; nullopt after printing a usage error to ctx.io.err.
  virtual std::optional<std::vector<const NodeDecl*>> select(const Recipe& recipe, CommandContext& ctx);
  // Usage errors that need the recipe or the selection: prints one and returns kExitUsage, or
  // returns nullopt. Also the place to settle options from what was parsed.
  virtual std::optional<int> check_usage(const Recipe& /*recipe*/,
                                         const std::vector<const NodeDecl*>& /*selected*/,
                                         CommandContext& /*ctx*/) {
    return std::nullopt;
  }
  // What to build before checking (default: the selected nodes themselves).
  virtual std::vector<std::string> targets(const std::vector<const NodeDecl*>& selected) const;
  // Runs once after the build, before the first node (e.g. creates a renderer). Throws
  // std::exception when the checks cannot run: the command prints "error: <what>" and exits 1.
  virtual void prepare(CommandContext& /*ctx*/) {}
  // Checks one node and writes its report under `report_dir` (a StagedReportDir, so an
  // interrupted or failed check leaves no partial report). Returns kExitOk (passed),
  // kExitBuildFailed (failed; fail_node() says why) or kExitInterrupted (stopped by the cancel
  // flag; the caller prints the line).
  virtual int check_node(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& node,
                         const std::filesystem::path& report_dir, CommandContext& ctx) = 0;

  // "error: node 'N' (stage S): what" on ctx.io.err, and the node's report directory removed (an
  // older run's report must not pass for this one's). Returns kExitBuildFailed.
  int fail_node(const NodeDecl& node, const std::filesystem::path& report_dir, const std::string& what,
                CommandContext& ctx) const;
  // Runs `check` (a node's check, up to its report's commit) and returns its result; what it
  // throws becomes the result instead: Cancelled kExitInterrupted, any other std::exception
  // fail_node() with its message (a one-line reason: unreadable outputs, a render failure, an
  // unwritable report).
  int guarded(const NodeDecl& node, const std::filesystem::path& report_dir, CommandContext& ctx,
              const std::function<int()>& check) const;
  // For the render sinks, called after each view (where Ctrl-C or SIGTERM stops a long check):
  // throws Cancelled once the cancel flag is set, else says whether to write the view's images
  // (false with --no-images).
  bool keep_images(const CommandContext& ctx) const;
  // Writes `json` (indented by 2, with a final newline) to `file` through ctx.fs; throws
  // std::runtime_error("cannot write <file>") if it cannot.
  static void write_json_report(const std::filesystem::path& file, const nlohmann::json& json,
                                CommandContext& ctx);
  // --pixel-threshold, --max-failing-fraction and --max-coverage-error, as lodcheck and
  // impostorcheck spell them, bound to the three values. Returns --pixel-threshold's option
  // (count() == 0: not given, so the node's pixel error decides).
  static CLI::Option* add_coverage_thresholds(CLI::App& sub, double& pixel_threshold,
                                              double& max_failing_fraction, double& max_coverage_error);

  const CheckCommandSpec& spec() const { return spec_; }
  const std::string& recipe_file() const { return recipe_; }
  const std::vector<std::string>& node_names() const { return nodes_; }
  bool no_images() const { return no_images_; }
  // "sylva <name>", as messages begin.
  std::string command_name() const { return std::string("sylva ") + spec_.name; }

 private:
  CheckCommandSpec spec_;
  std::string recipe_ = "configs/default.yaml";
  std::vector<std::string> nodes_;
  int jobs_ = 0;
  std::string report_root_;
  bool no_images_ = false;
};

}  // namespace sylva
