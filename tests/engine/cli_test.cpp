// The command line: exit codes, messages and the --json summary, driven through run_cli with
// test stages and captured output.
#include "app/cli.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "pipeline/digest.h"
#include "tests/engine/test_stages.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

struct Captured {
  int code;
  std::string out, err;
};

class CliTest : public ::testing::Test {
 protected:
  CliTest() { test::register_test_stages(reg_, &log_); }

  Captured run(std::vector<std::string> args) {
    args.insert(args.begin(), {"sylva"});
    std::vector<std::string> with_dirs = {args[0], "--out", (dir_ / "out").string()};
    with_dirs.insert(with_dirs.end(), args.begin() + 1, args.end());
    std::vector<const char*> argv;
    for (auto& a : with_dirs) argv.push_back(a.c_str());
    std::FILE* out = std::tmpfile();
    std::FILE* err = std::tmpfile();
    RealFileSystem fsys;
    SteadyClock clock;
    CommandContext ctx{fsys, clock, reg_, CliIo{out, err, false, nullptr}, {}};
    const int code = run_cli(static_cast<int>(argv.size()), argv.data(), ctx);
    return {code, test::read_and_close(out), test::read_and_close(err)};
  }
  std::string recipe(const std::string& yaml) {
    test::write_file(dir_ / "r.yaml", yaml);
    return (dir_ / "r.yaml").string();
  }

  test::TempDir dir_;
  StageRegistry reg_;
  test::RunLog log_;
};

TEST_F(CliTest, BuildJsonSummaryCountsBuiltThenCached) {
  const auto r =
      recipe("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n  b:\n    stage: concat\n    needs: a\n");
  auto c1 = run({"build", r, "--json", "-j", "2"});
  ASSERT_EQ(c1.code, 0) << c1.err;
  auto j1 = nlohmann::json::parse(c1.out);
  EXPECT_EQ(j1["built"], 2);
  EXPECT_EQ(j1["cached"], 0);
  EXPECT_EQ(j1["nodes"][0]["name"], "a");
  EXPECT_EQ(j1["nodes"][0]["outputs"][0]["sha256"], sha256_hex("hello\n"));
  EXPECT_NE(c1.err.find("[1/2] built a"), std::string::npos);  // plain per-node log lines
  auto j2 = nlohmann::json::parse(run({"build", r, "--json"}).out);
  EXPECT_EQ(j2["built"], 0);
  EXPECT_EQ(j2["cached"], 2);
  EXPECT_EQ(j2["removed"], nlohmann::json::array());
  // Node b dropped from the recipe: its directory goes, and the build says so.
  const auto r2 = recipe("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n");
  const std::string b_dir = (dir_ / "out" / "r" / "b").string() + "/";
  auto dry = run({"build", r2, "--dry-run"});
  EXPECT_NE(dry.err.find("sylva: would remove " + b_dir + " (node 'b' is no longer in the recipe)\n"),
            std::string::npos)
      << dry.err;
  auto c3 = run({"build", r2, "--json"});
  ASSERT_EQ(c3.code, 0) << c3.err;
  EXPECT_EQ(nlohmann::json::parse(c3.out)["removed"], nlohmann::json::array({"b"}));
  EXPECT_NE(c3.err.find("sylva: removed " + b_dir + " (node 'b' is no longer in the recipe)\n"),
            std::string::npos)
      << c3.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out" / "r" / "b"));
}

TEST_F(CliTest, TargetTakesOneNodeSoTheRecipeMayFollowIt) {
  const auto r = recipe(
      "version: 1\nname: r\nnodes:\n  a:\n    stage: text\n  b:\n    stage: text\n    with: { text: b }\n"
      "  c:\n    stage: concat\n"
      "    needs: [a, b]\n");
  auto c = run({"build", "--target", "a", r, "--json"});
  ASSERT_EQ(c.code, 0) << c.err;
  const auto j = nlohmann::json::parse(c.out);
  EXPECT_EQ(j["built"], 1);
  EXPECT_EQ(j["nodes"].size(), 1u);
  EXPECT_EQ(j["nodes"][0]["name"], "a");
  // Repeated, each --target adds its node.
  auto c2 = run({"build", r, "--target", "a", "--target", "b", "--json"});
  ASSERT_EQ(c2.code, 0) << c2.err;
  const auto j2 = nlohmann::json::parse(c2.out);
  EXPECT_EQ(j2["nodes"].size(), 2u);
  EXPECT_EQ(j2["built"], 1);
  EXPECT_EQ(j2["cached"], 1);
}

TEST_F(CliTest, RecipeErrorExitsTwoWithPositionAndCaret) {
  const auto r = recipe("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { count: x }\n");
  auto c = run({"build", r});
  EXPECT_EQ(c.code, 2);
  EXPECT_EQ(c.err, r +
                       ":6:20: error: wrong type: parameter 'count' expects int, got 'x'\n"
                       "      with: { count: x }\n"
                       "                     ^\n"
                       "1 error in recipe " +
                       r + "\n");
  EXPECT_EQ(log_.total(), 0);
}

TEST_F(CliTest, FailedNodeExitsOneAndNamesTheNode) {
  const auto r = recipe("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { fail: true }\n");
  auto c = run({"build", r});
  EXPECT_EQ(c.code, 1);
  EXPECT_NE(c.err.find("error: node 'a' (stage text): asked to fail\n"), std::string::npos) << c.err;
}

TEST_F(CliTest, UsageErrorsExitTwo) {
  EXPECT_EQ(run({"frobnicate"}).code, 2);
  EXPECT_EQ(run({"build", "-j", "0"}).code, 2);
  auto h = run({"--help"});
  EXPECT_EQ(h.code, 0);
  EXPECT_NE(h.out.find("build"), std::string::npos);
}

TEST_F(CliTest, StagesListsParametersWithTypesAndDefaults) {
  auto c = run({"stages"});
  EXPECT_EQ(c.code, 0);
  EXPECT_NE(c.out.find("text (v1): writes a line of text (test stage)"), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("scale"), std::string::npos);
  EXPECT_NE(c.out.find("real [0.0, 10.0]"), std::string::npos);
}

TEST_F(CliTest, GraphAndExplain) {
  const auto r =
      recipe("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n  b:\n    stage: concat\n    needs: a\n");
  auto g = run({"graph", r});
  EXPECT_EQ(g.out, "a (text)\nb (concat) <- a\n");
  auto dot = run({"graph", r, "--dot"});
  EXPECT_NE(dot.out.find("\"a\" -> \"b\";"), std::string::npos);
  EXPECT_EQ(run({"explain", r, "b"}).out.substr(0, 32), "'b' will rebuild because its inp");
  run({"build", r});
  EXPECT_EQ(run({"explain", r, "b"}).out.substr(0, 26), "'b' is up to date (action ");
  auto bad = run({"explain", r, "c"});
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(bad.err, "error: no node 'c' in recipe 'r'; did you mean 'a'?\n");
}

TEST_F(CliTest, CleanAndCacheCommands) {
  const auto r = recipe("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n");
  run({"build", r});
  EXPECT_TRUE(std::filesystem::exists(dir_ / "out/r/a/out.txt"));
  auto st = run({"cache", "stats"});
  EXPECT_NE(st.out.find("1 blobs (6 B), 1 action results"), std::string::npos) << st.out;
  EXPECT_EQ(run({"clean", r}).code, 0);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out/r"));
  EXPECT_EQ(run({"cache", "verify"}).out, "0 corrupt blobs removed, 0 invalid action results removed\n");
  EXPECT_EQ(run({"clean", "--all"}).code, 0);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out"));
}

// Issue 15 item 10: `clean --all` deletes only what sylva made. `--out .` used to empty a
// project and `--cache ..` its parent; now a project's own files, CMake's build folder and a
// foreign cache directory stay.
TEST_F(CliTest, CleanAllDeletesOnlyWhatSylvaMade) {
  const auto r = recipe("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n");
  ASSERT_EQ(run({"build", r}).code, 0);
  EXPECT_TRUE(std::filesystem::exists(dir_ / "out/cache/CACHEDIR.TAG"));
  test::write_file(dir_ / "out/build/CMakeCache.txt", "cmake\n");  // the tool folders beside
  test::write_file(dir_ / "out/notes.txt", "mine\n");
  auto c = run({"clean", "--all"});
  EXPECT_EQ(c.code, 0);
  EXPECT_EQ(c.err,
            "sylva clean: kept 2 entries that sylva did not create (in " + (dir_ / "out").string() + ")\n");
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out/r"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out/cache"));
  EXPECT_TRUE(std::filesystem::exists(dir_ / "out/build/CMakeCache.txt"));
  EXPECT_TRUE(std::filesystem::exists(dir_ / "out/notes.txt"));

  // A --cache that names a directory sylva did not make is kept, whatever is in it.
  test::write_file(dir_ / "project/src.txt", "code\n");
  c = run({"--cache", (dir_ / "project").string(), "clean", "--all"});
  EXPECT_EQ(c.code, 0);
  EXPECT_NE(c.err.find("sylva clean: kept " + (dir_ / "project").string() + ": not a sylva cache"),
            std::string::npos)
      << c.err;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "project/src.txt"));
}

}  // namespace
}  // namespace sylva
