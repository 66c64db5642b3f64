// Issue 15's recipe items, each as the attack or accident that used to succeed: reading files
// outside the project and echoing them (1), resource bombs (2), names that clash with the out
// dir's neighbours (3), terminal bytes and secrets in diagnostics (12), parameter constraints
// found only when a node ran and `stage: [x]` (14). Every expectation is the exact message.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "pipeline/project_root.h"
#include "pipeline/recipe_loader.h"
#include "tests/engine/test_stages.h"
#include "tests/support/test_support.h"

namespace sylva {
namespace {

namespace fs = std::filesystem;

class UntrustedRecipeTest : public ::testing::Test {
 protected:
  UntrustedRecipeTest() {
    test::register_test_stages(reg_, nullptr);
    fs::create_directories(dir_ / "project");
    test::write_file(dir_ / "secret.txt", "root:*:20228:0:99999:7:::\n");
  }

  // Writes `yaml` as project/r.yaml and loads it with `options`.
  std::optional<Recipe> load(const std::string& yaml, LoadOptions options = {}) {
    test::write_file(dir_ / "project/r.yaml", yaml);
    diags_ = Diagnostics(options.limits.errors);
    return load_recipe(dir_ / "project/r.yaml", reg_, fs_, diags_, options);
  }
  // Messages with the temp dir's path replaced by "T".
  std::string errors() const { return relative(diags_.str()); }
  std::string pretty() const { return relative(diags_.pretty()); }
  std::string relative(std::string s) const {
    const std::string prefix = fs::weakly_canonical(dir_.path()).string();
    for (std::size_t p; (p = s.find(prefix)) != std::string::npos;) s.replace(p, prefix.size(), "T");
    const std::string raw = dir_.path().string();
    for (std::size_t p; (p = s.find(raw)) != std::string::npos;) s.replace(p, raw.size(), "T");
    return s;
  }

  test::TempDir dir_;
  StageRegistry reg_;
  RealFileSystem fs_;
  Diagnostics diags_;
};

constexpr const char* kHow =
    "' (a recipe may only name files below its directory or the directories its 'root:' key declares; pass "
    "--allow-outside-root to trust this recipe)";

// Item 1: path parameters, include: and !include may not leave the project root, symbolic
// links included; nothing of the foreign file is read, let alone echoed.
TEST_F(UntrustedRecipeTest, PathsOutsideTheProjectRootAreRefused) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: readfile\n    with: { file: ../secret.txt }\n"));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:6:19: error: parameter 'file': 'T/secret.txt' is outside the project root "
            "'T/project" +
                std::string(kHow) + "\n");

  EXPECT_FALSE(load("version: 1\nname: r\ninclude: ../secret.txt\n"));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:3:10: error: include 'T/secret.txt' is outside the project root 'T/project" +
                std::string(kHow) + "\n");

  EXPECT_FALSE(load("version: 1\nname: r\ndefaults: !include ../secret.txt\n"));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:3:11: error: !include 'T/secret.txt' is outside the project root "
            "'T/project" +
                std::string(kHow) + "\n");
  EXPECT_EQ(errors().find("root:*"), std::string::npos);

  fs::create_symlink(dir_ / "secret.txt", dir_ / "project/link.txt");  // inside by name only
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: readfile\n    with: { file: link.txt }\n"));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:6:19: error: parameter 'file': 'T/project/link.txt' is outside the "
            "project root 'T/project" +
                std::string(kHow) + "\n");
}

// Directories are resolved once per recipe (a 10,000-file recipe costs one lstat per file):
// a linked directory is judged by where it points for every file in it, a linked file among
// plain ones by its own target, and ".." after a link by the real path.
TEST_F(UntrustedRecipeTest, LinkedDirectoriesAndFilesAreJudgedByTheirTargets) {
  fs::create_directories(dir_ / "outside");
  fs::create_directories(dir_ / "project/in");
  for (const char* f : {"outside/a.txt", "outside/b.txt", "project/in/a.txt", "project/in/b.txt"})
    test::write_file(dir_ / f, "data\n");
  fs::create_directory_symlink(dir_ / "outside", dir_ / "project/ext");  // inside by name only
  fs::create_symlink(dir_ / "secret.txt", dir_ / "project/in/c.txt");
  fs::create_directories(dir_ / "project/deep");
  fs::create_directory_symlink(dir_ / "project/in", dir_ / "project/deep/up");  // stays inside
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n"
           "  a:\n    stage: readfile\n    with: { file: in/a.txt }\n"
           "  b:\n    stage: readfile\n    with: { file: ext/a.txt }\n"
           "  c:\n    stage: readfile\n    with: { file: in/b.txt }\n"
           "  d:\n    stage: readfile\n    with: { file: ext/b.txt }\n"
           "  e:\n    stage: readfile\n    with: { file: in/c.txt }\n"
           "  f:\n    stage: readfile\n    with: { file: deep/up/a.txt }\n"));
  const std::string outside = "' is outside the project root 'T/project" + std::string(kHow) + "\n";
  EXPECT_EQ(errors(), "T/project/r.yaml:9:19: error: parameter 'file': 'T/project/ext/a.txt" + outside +
                          "T/project/r.yaml:15:19: error: parameter 'file': 'T/project/ext/b.txt" + outside +
                          "T/project/r.yaml:18:19: error: parameter 'file': 'T/project/in/c.txt" + outside);
  const ProjectRoot root(dir_ / "project");
  EXPECT_TRUE(root.contains(dir_ / "project/in/a.txt"));
  EXPECT_FALSE(root.contains(dir_ / "project/ext/a.txt"));
  EXPECT_FALSE(root.contains(dir_ / "project/ext/missing.txt"));
  EXPECT_TRUE(root.contains(dir_ / "project/in/missing.txt"));
  EXPECT_TRUE(root.contains(dir_ / "project/deep/up/../in/a.txt"));    // deep/up -> in, ".." -> project
  EXPECT_FALSE(root.contains(dir_ / "project/ext/../../secret.txt"));  // ext -> outside, ".." -> T
  EXPECT_FALSE(root.contains(dir_ / "project/../secret.txt"));
  EXPECT_TRUE(root.contains(dir_ / "project"));
  EXPECT_FALSE(root.contains(dir_ / "projectile/a.txt"));
}

TEST_F(UntrustedRecipeTest, TheRootCanBeDeclaredBoundedOrLifted) {
  const std::string reads_secret = "nodes:\n  a:\n    stage: readfile\n    with: { file: ../secret.txt }\n";
  // A declared root that holds the file, alone or in a list (sources here, data elsewhere).
  EXPECT_TRUE(load("version: 1\nname: r\nroot: ..\n" + reads_secret)) << errors();
  fs::create_directories(dir_ / "data");
  test::write_file(dir_ / "data/in.txt", "data\n");
  EXPECT_TRUE(
      load("version: 1\nname: r\nroot: [., ../data, ../not-downloaded]\nnodes:\n  a:\n    stage: readfile\n"
           "    with: { file: ../data/in.txt }\n"))
      << errors();
  EXPECT_FALSE(load("version: 1\nname: r\nroot: [., ../data]\n" + reads_secret));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:7:19: error: parameter 'file': 'T/secret.txt' is outside the project roots "
            "'T/project', 'T/data" +
                std::string(kHow) + "\n");
  // ... unless whoever runs sylva bounded it (--root): then the declaration may not leave it.
  LoadOptions bounded;
  bounded.root = dir_ / "project";
  EXPECT_FALSE(load("version: 1\nname: r\nroot: ..\n" + reads_secret, bounded));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:3:7: error: 'root' names 'T', outside the root given by --root "
            "('T/project')\n");
  // --allow-outside-root: a trusted recipe reads anything.
  LoadOptions trusted;
  trusted.confine = false;
  EXPECT_TRUE(load("version: 1\nname: r\n" + reads_secret, trusted)) << errors();
  // `root:` only in the top-level recipe.
  test::write_file(dir_ / "project/frag.yaml", "root: /\n");
  EXPECT_FALSE(load("version: 1\nname: r\ninclude: frag.yaml\n"));
  EXPECT_EQ(errors(), "T/project/frag.yaml:1:1: error: 'root' is only allowed in the top-level recipe\n");
}

// Item 2: a FIFO or device as a parameter is refused at load time (reading it would block).
TEST_F(UntrustedRecipeTest, NonRegularFilesAreRefused) {
  ASSERT_EQ(::mkfifo((dir_ / "project/fifo").c_str(), 0600), 0);
  EXPECT_FALSE(load("version: 1\nname: r\nnodes:\n  a:\n    stage: readfile\n    with: { file: fifo }\n"));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:6:19: error: parameter 'file' names 'T/project/fifo', which is not a "
            "regular file\n");
  EXPECT_FALSE(load("version: 1\nname: r\ninclude: fifo\n"));
  EXPECT_EQ(errors(), "T/project/r.yaml:3:10: error: cannot read 'T/project/fifo': not a regular file\n");
  LoadOptions trusted;
  trusted.confine = false;
  EXPECT_FALSE(load("version: 1\nname: r\ninclude: /dev/zero\n", trusted));
  EXPECT_EQ(errors(), "T/project/r.yaml:3:10: error: cannot read '/dev/zero': not a regular file\n");
}

// Item 2: the billion laughs stops at the node limit, in well under a second.
TEST_F(UntrustedRecipeTest, AliasBombStopsAtTheYamlNodeLimit) {
  std::string y = "a0: &a0 [x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 9; ++i) {
    y += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 9; ++k) y += std::string(k ? ", " : "") + "*a" + std::to_string(i - 1);
    y += "]\n";
  }
  EXPECT_FALSE(load(y));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:1:1: error: 'T/project/r.yaml' expands to more than 1000000 YAML nodes "
            "(aliases count once per use); raise the limit with --limit yaml-nodes=N\n");
}

// The fuzzer's stack overflow (ASan): a few hundred nested flow sequences, fewer than yaml-cpp
// itself refuses (it says "bad file" at about 500).
TEST_F(UntrustedRecipeTest, DeepNestingStopsAtTheDepthLimit) {
  EXPECT_FALSE(load("version: 1\nname: r\nx: " + std::string(300, '[') + std::string(300, ']') + "\n"));
  EXPECT_EQ(errors(), "T/project/r.yaml:3:131: error: YAML nested deeper than 128 levels\n");
  // 100 levels pass the reader: the only error is the recipe's own.
  EXPECT_FALSE(load("version: 1\nname: r\nx: " + std::string(100, '[') + std::string(100, ']') + "\n"));
  EXPECT_EQ(errors().substr(0, 44), "T/project/r.yaml:3:1: error: unknown key 'x'");
}

TEST_F(UntrustedRecipeTest, FileSizeIncludeDepthMatrixNodesAndErrorsAreCapped) {
  LoadOptions small;
  small.limits.file_bytes = 64;
  EXPECT_FALSE(load("version: 1\nname: r\n# " + std::string(100, 'x') + "\n", small));
  EXPECT_EQ(errors(),
            "error: cannot read 'T/project/r.yaml': larger than 64 bytes; raise the limit with --limit "
            "file-bytes=N\n");

  for (int i = 0; i < 20; ++i)
    test::write_file(dir_ / ("project/i" + std::to_string(i) + ".yaml"),
                     "include: i" + std::to_string(i + 1) + ".yaml\n");
  test::write_file(dir_ / "project/i20.yaml", "description: deep\n");
  EXPECT_FALSE(load("version: 1\nname: r\ninclude: i0.yaml\n"));
  EXPECT_EQ(errors(),
            "T/project/i15.yaml:1:10: error: includes nested deeper than 16 files; raise the limit with "
            "--limit include-depth=N\n");

  // 10^8 combinations: refused before expanding (it used to run for minutes, even with --dry-run).
  std::string m = "version: 1\nname: r\nmatrix:\n";
  for (int v = 0; v < 8; ++v) m += "  v" + std::to_string(v) + ": [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]\n";
  m += "nodes:\n  n_${v0}${v1}${v2}${v3}${v4}${v5}${v6}${v7}:\n    stage: text\n";
  EXPECT_FALSE(load(m));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:13:3: error: node 'n_${v0}${v1}${v2}${v3}${v4}${v5}${v6}${v7}' expands to more "
            "than 10000 nodes over its matrix; raise the limit with --limit matrix=N\n");

  LoadOptions few;
  few.limits.nodes = 3;
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a: {stage: text}\n  b: {stage: text}\n  c: {stage: text}\n"
           "  d: {stage: text}\n",
           few));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:1:1: error: the recipe has more than 3 nodes; raise the limit with "
            "--limit nodes=N\n");

  std::string broken = "version: 1\nname: r\nnodes:\n";
  for (int i = 0; i < 150; ++i) broken += "  n" + std::to_string(i) + ": {stage: nope}\n";
  EXPECT_FALSE(load(broken));
  EXPECT_EQ(diags_.all().size(), 100u);
  EXPECT_EQ(diags_.size(), 100u);                // the rest were not even looked at
  EXPECT_EQ(diags_.all().back().loc.line, 103);  // n99's line: the first hundred were kept
  LoadOptions five;
  five.limits.errors = 5;
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a: 1\n  b: 2\n  c: 3\n  d: 4\n  e: 5\n  f: 6\n  g: 7\n", five));
  EXPECT_EQ(diags_.all().size(), 5u);

  EXPECT_EQ(set_limit(small.limits, "nodes=7"), std::nullopt);
  EXPECT_EQ(small.limits.nodes, 7u);
  EXPECT_EQ(set_limit(small.limits, "nodes=0"), "limit 'nodes' needs a positive integer, as in nodes=1000");
  EXPECT_EQ(set_limit(small.limits, "bogus=1"),
            "unknown limit 'bogus' (file-bytes, yaml-nodes, include-depth, matrix, nodes, errors)");
}

// Diagnostics::dropped line: what was not shown is counted.
TEST(DiagnosticsTest, ErrorsBeyondTheCapAreCountedNotKept) {
  Diagnostics d(2);
  for (int i = 0; i < 5; ++i) d.error({"r.yaml", i + 1, 1}, "bad " + std::to_string(i));
  EXPECT_EQ(d.size(), 5u);
  EXPECT_EQ(d.str(),
            "r.yaml:1:1: error: bad 0\nr.yaml:2:1: error: bad 1\n"
            "sylva: 3 more errors not shown (at most 2 are; raise it with --limit errors=N)\n");
}

// Item 3: a recipe named like the out dir's neighbours, or a node named like its bookkeeping.
TEST_F(UntrustedRecipeTest, ReservedNamesAreRefused) {
  for (const char* name : {"cache", "build", "npm", ".hidden"}) {
    EXPECT_FALSE(load(std::string("version: 1\nname: ") + name + "\n")) << name;
    EXPECT_EQ(errors(),
              std::string("T/project/r.yaml:2:7: error: reserved recipe name '") + name +
                  "': out/cache, out/build, out/npm, out/test-images, out/tmp and names starting with '.' "
                  "belong to sylva and the build; choose another name\n");
  }
  EXPECT_FALSE(load("version: 1\nname: r\nnodes:\n  .sylva:\n    stage: text\n"));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:4:3: error: reserved node name '.sylva': names starting with '.' belong to "
            "sylva's bookkeeping in the out dir\n");
}

// Item 12: recipe bytes are printed escaped (no terminal escape, bell or NUL reaches the
// terminal), foreign values are cut to a short excerpt, long source lines to a window.
TEST_F(UntrustedRecipeTest, DiagnosticsEscapeAndCutWhatTheyQuote) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { \"x\\e[31m\\a\": 1 }\n"));
  EXPECT_EQ(errors(), "T/project/r.yaml:6:13: error: unknown parameter 'x\\x1b[31m\\x07' for stage 'text'\n");
  const std::string shown = pretty();
  EXPECT_EQ(shown.find('\x1b'), std::string::npos);
  EXPECT_EQ(shown.find('\a'), std::string::npos);

  EXPECT_FALSE(load("version: 1\nname: r\nnodes:\n  a:\n    stage: text\n    with: { mode: " +
                    std::string(300, 'q') + " }\n"));
  EXPECT_EQ(errors(), "T/project/r.yaml:6:19: error: parameter 'mode' must be one of plain, upper, got '" +
                          std::string(40, 'q') + "...'\n");
  // The caret line: at most 60 bytes either side of the column.
  const std::string p = pretty();
  const std::size_t line_start = p.find("\n  ") + 3;
  const std::string line = p.substr(line_start, p.find('\n', line_start) - line_start);
  EXPECT_EQ(line, "    with: { mode: " + std::string(60, 'q') + "...");

  EXPECT_EQ(escape_bytes(std::string("a\0b\x7f\xc2\x9b"
                                     "c\xc3\xa9",
                                     9)),
            "a\\x00b\\x7f\\xc2\\x9bc\xc3\xa9");
  EXPECT_EQ(excerpt("\xc3\xa9\xc3\xa9\xc3\xa9", 3), "\xc3\xa9...");  // cut at a character boundary
}

// Item 14: constraints known at load time fail at load time, at the value's position.
TEST_F(UntrustedRecipeTest, ParameterConstraintsAreCheckedWhenLoading) {
  EXPECT_FALSE(
      load("version: 1\nname: r\nnodes:\n  a:\n    stage: constrained\n    with: { size: 24, "
           "levels: [0.1, 0.3, 0.2] }\n"));
  EXPECT_EQ(
      errors(),
      "T/project/r.yaml:6:19: error: value out of range: parameter 'size' must be a power of two, got 24\n"
      "T/project/r.yaml:6:42: error: value out of range: parameter 'levels' must be increasing, but item 2 "
      "(0.2) is not greater than item 1 (0.3)\n");
  EXPECT_TRUE(load(
      "version: 1\nname: r\nnodes:\n  a:\n    stage: constrained\n    with: { size: 32, levels: [1, 2] }\n"))
      << errors();
}

TEST_F(UntrustedRecipeTest, StageGivenAsAListSaysHowToWriteIt) {
  EXPECT_FALSE(load("version: 1\nname: r\nnodes:\n  a:\n    stage: [text]\n"));
  EXPECT_EQ(errors(),
            "T/project/r.yaml:5:12: error: 'stage' must be one stage name, got a list (write 'stage: "
            "text')\n");
}

}  // namespace
}  // namespace sylva
