// The check-command kit (app/check_command.h, app/command_context.h) on the in-memory file system
// and a fake clock: a small check command over the `text` test stage, run through run_cli as
// `sylva textcheck`, selects nodes, reports usage errors with the exact text of the real check
// commands (lodcheck, impostorcheck, verify), builds what it checks and writes its reports, all
// without touching the disk.
#include "app/check_command.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/cli.h"
#include "tests/engine/test_stages.h"
#include "tests/support/fake_clock.h"
#include "tests/support/fake_filesystem.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

constexpr CheckCommandSpec kTextCheck{
    "textcheck",
    "text",
    "docs/test.md",
    "textcheck",
    "check that text nodes start with a prefix (test command)",
    "check only this text node (repeatable; default: every node of stage text)",
    "parallel nodes while building (default: all cores)",
    "where reports go (default: <out>/<recipe>/textcheck)",
    nullptr,
};

// Copies each node's out.txt into its report directory and passes when it starts with --expect.
class TextCheck final : public CheckCommand {
 public:
  TextCheck() : CheckCommand(kTextCheck) {}
  std::vector<std::string> checked;

 protected:
  void add_options(CLI::App& sub) override { sub.add_option("--expect", expect_, "the prefix"); }

  int check_node(const Recipe& recipe, const RecipeBuild& built, const NodeDecl& node,
                 const fs::path& report_dir, CommandContext& ctx) override {
    checked.push_back(node.name);
    const InputArtifact out = input_artifact(recipe, built, node.name);
    const ArtifactFile* f = out.file("out.txt");
    const std::optional<std::string> text = f ? ctx.fs.read(f->path) : std::nullopt;
    if (!text) return fail_node(node, report_dir, "no out.txt", ctx);
    StagedReportDir staged(ctx.fs, report_dir);
    write_json_report(staged.path() / "report.json", {{"text", *text}}, ctx);
    staged.commit();
    if (text->rfind(expect_, 0) != 0)
      return fail_node(node, report_dir, "does not start with '" + expect_ + "'", ctx);
    std::fprintf(ctx.io.out, "textcheck %s: ok\n", node.name.c_str());
    return kExitOk;
  }

 private:
  std::string expect_;
};

struct Captured {
  int code;
  std::string out, err;
};

class CheckCommandTest : public ::testing::Test {
 protected:
  CheckCommandTest() {
    test::register_test_stages(reg_, &log_);
    fs_.put("/p/r.yaml",
            "version: 1\nname: r\nnodes:\n"
            "  hello_a:\n    stage: text\n    with: { text: alpha }\n"
            "  hello_b:\n    stage: text\n    with: { text: beta }\n"
            "  joined:\n    stage: concat\n    needs: [hello_a, hello_b]\n");
  }

  // `sylva --out /o --cache /c textcheck ARGS...` on the fake file system.
  Captured run(std::vector<std::string> args) {
    std::vector<std::string> all = {"sylva", "--out", "/o", "--cache", "/c", "textcheck"};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<const char*> argv;
    for (auto& a : all) argv.push_back(a.c_str());
    std::FILE* out = std::tmpfile();
    std::FILE* err = std::tmpfile();
    CommandContext ctx{fs_, clock_, reg_, CliIo{out, err, false, &cancel_}, {}};
    command_ = std::make_unique<TextCheck>();
    const int code = run_cli(static_cast<int>(argv.size()), argv.data(), ctx, {command_.get()});
    return {code, test::read_and_close(out), test::read_and_close(err)};
  }

  test::FakeFileSystem fs_;
  test::FakeClock clock_;
  StageRegistry reg_;
  test::RunLog log_;
  std::atomic<bool> cancel_{false};
  std::unique_ptr<TextCheck> command_;
};

// Every usage error is one line and exit 2, before anything is built or written.
TEST_F(CheckCommandTest, UsageErrorsBuildAndWriteNothing) {
  Captured r = run({"/p/r.yaml", "--node", "hello_c"});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: no node 'hello_c' of stage 'text' in recipe 'r'; did you mean 'hello_a'?\n");
  r = run({"/p/r.yaml", "--node", "joined"});  // a node, but not of stage text
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "error: no node 'joined' of stage 'text' in recipe 'r'\n");
  fs_.put("/p/plain.yaml", "version: 1\nname: plain\nnodes:\n  n:\n    stage: nested\n");
  r = run({"/p/plain.yaml"});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err,
            "error: recipe 'plain' (/p/plain.yaml) has no node of stage 'text'; add one (docs/test.md)\n");
  fs_.put("/p/clash.yaml", "version: 1\nname: clash\nnodes:\n  textcheck:\n    stage: text\n");
  r = run({"/p/clash.yaml"});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err,
            "error: recipe 'clash' has a node named 'textcheck', whose outputs would mix with the reports; "
            "choose another directory with --report-dir\n");
  r = run({"/p/missing.yaml"});
  EXPECT_EQ(r.code, 2);
  r = run({"/p/r.yaml", "-j", "0"});  // the shared options' checks are CLI11's
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(log_.total(), 0);
  EXPECT_TRUE(fs_.writes.empty()) << ::testing::PrintToString(fs_.writes);
}

// Named nodes are checked in the order given, once each; each report lands in its own directory
// under <out>/<recipe>/textcheck/, in the fake file system.
TEST_F(CheckCommandTest, ChecksTheNamedNodesInOrderIntoTheirReportDirectories) {
  const Captured r = run({"/p/r.yaml", "--node", "hello_b", "--node", "hello_a", "--node", "hello_b"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "textcheck hello_b: ok\ntextcheck hello_a: ok\n");
  EXPECT_EQ(command_->checked, (std::vector<std::string>{"hello_b", "hello_a"}));
  EXPECT_EQ(log_.count("joined"), 0);  // only what the checks read was built
  EXPECT_EQ(fs_.files.at("/o/r/textcheck/hello_a/report.json"), "{\n  \"text\": \"alpha\\n\"\n}\n");
  EXPECT_EQ(fs_.files.at("/o/r/hello_b/out.txt"), "beta\n");
  EXPECT_FALSE(fs::exists("/o/r/textcheck"));  // nothing on the real disk
}

// A node that fails its check loses its report directory and makes the exit code 1; the other
// nodes are still checked. --report-dir moves the reports.
TEST_F(CheckCommandTest, AFailedNodeLeavesNoReportAndExitsOne) {
  const Captured r = run({"/p/r.yaml", "--expect", "al", "--report-dir", "/reports"});
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.out, "textcheck hello_a: ok\n");
  // After the build's log lines ("[1/2] built hello_a ..."): the node's one line.
  EXPECT_TRUE(r.err.ends_with("\nerror: node 'hello_b' (stage text): does not start with 'al'\n")) << r.err;
  EXPECT_EQ(command_->checked, (std::vector<std::string>{"hello_a", "hello_b"}));
  EXPECT_TRUE(fs_.files.count("/reports/hello_a/report.json"));
  EXPECT_FALSE(fs_.files.count("/reports/hello_b/report.json"));
  EXPECT_FALSE(fs_.files.count("/o/r/textcheck/hello_a/report.json"));
}

// Ctrl-C (the context's cancel flag) stops the command with one line and exit 130.
TEST_F(CheckCommandTest, CancelEndsWithOneLineAndExit130) {
  cancel_ = true;
  const Captured r = run({"/p/r.yaml"});
  EXPECT_EQ(r.code, 130);
  EXPECT_TRUE(r.err.ends_with(
      "sylva textcheck: interrupted; nothing more was written (earlier reports are as they were)\n"))
      << r.err;
  EXPECT_TRUE(command_->checked.empty());
}

}  // namespace
}  // namespace sylva
