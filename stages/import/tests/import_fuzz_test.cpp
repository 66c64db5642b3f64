// Fuzz-style robustness: truncated and mutated versions of real files must either import to a
// valid tree or fail with one clean ImportError / TreeFormatError — never crash, hang, or
// throw anything else. Deterministic (fixed seed) so a failure reproduces; a libFuzzer-style
// harness could reuse check_one().
#include <gtest/gtest.h>

#include <cstdint>
#include <random>

#include "libs/tree/sylt_format.h"
#include "stages/import/import_error.h"
#include "stages/import/import_file.h"
#include "tests/support/test_support.h"

namespace sylva::import {
namespace {

// Imports `bytes` with auto detection; returns "ok", "import" or "format" (which error).
std::string check_one(const std::string& bytes, const char* name) {
  try {
    const tree::Tree t = import_tree(bytes, name, {});
    EXPECT_EQ(tree::validate_tree(t), std::vector<std::string>{}) << "valid import of a mutation";
    return "ok";
  } catch (const ImportError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(std::string(name) + ":", 0), 0u) << e.what();
    EXPECT_GE(e.line(), 1);
    return "import";
  } catch (const tree::TreeFormatError&) {
    return "format";
  }
}

std::string mutate(std::string s, std::mt19937_64& rng) {
  static constexpr char kBytes[] = {'0', '1',  '9', '-', '.', ',',  '\t',
                                    ' ', '\n', 'e', 'n', '#', '\0', '\xff'};
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int k = 0; k < edits && !s.empty(); ++k) {
    const std::size_t at = rng() % s.size();
    switch (rng() % 4) {
      case 0:
        s[at] = kBytes[rng() % sizeof kBytes];
        break;  // replace
      case 1:
        s.erase(at, 1 + rng() % 8);
        break;  // delete
      case 2:
        s.insert(at, 1, kBytes[rng() % sizeof kBytes]);
        break;  // insert
      default:
        s.insert(at, s.substr(rng() % s.size(), 1 + rng() % 40));
        break;  // duplicate
    }
  }
  return s;
}

void fuzz_file(const char* file, int mutations) {
  const auto data = test::data_dir();
  if (!data) GTEST_SKIP() << "no test data (SYLVA_DATA_DIR)";
  // A slice keeps each import fast; the header and the first rows are where variety matters.
  std::string bytes = test::read_file(*data / "qsm" / file);
  std::size_t cut = 0;
  for (int lines = 0; lines < 120 && cut != std::string::npos; ++lines) cut = bytes.find('\n', cut + 1);
  if (cut != std::string::npos) bytes.resize(cut + 1);

  EXPECT_EQ(check_one(bytes, file), "ok");
  // Every truncation point in the first 3 rows, then every 97th byte.
  for (std::size_t n = 0; n < bytes.size(); n += n < 600 ? 1 : 97) check_one(bytes.substr(0, n), file);
  std::mt19937_64 rng(20240611);
  int errors = 0;
  for (int i = 0; i < mutations; ++i) errors += check_one(mutate(bytes, rng), file) != "ok";
  EXPECT_GT(errors, 0);  // the mutations do reach the error paths
}

TEST(ImportFuzz, SimpleForestCsv) { fuzz_file("rTwig_QSM.csv", 1500); }
TEST(ImportFuzz, TreeQsmTsv) { fuzz_file("rTwig_QSM_mat_TreeQSM241_cylinders.tsv", 1500); }
TEST(ImportFuzz, CanopyHydroCsv) { fuzz_file("canopyHydro_5_SmallTree.csv", 1500); }

// Truncated and bit-flipped .sylt bytes.
TEST(ImportFuzz, Sylt) {
  const auto data = test::data_dir();
  if (!data) GTEST_SKIP() << "no test data (SYLVA_DATA_DIR)";
  const auto path = *data / "qsm" / "rTwig_QSM.csv";
  const std::string sylt = tree::encode_sylt(import_tree(test::read_file(path), "t.csv", {}));
  for (std::size_t n = 0; n < sylt.size(); n += 1 + n / 16) check_one(sylt.substr(0, n), "t.sylt");
  std::mt19937_64 rng(7);
  for (int i = 0; i < 300; ++i) {
    std::string s = sylt;
    s[rng() % s.size()] ^= static_cast<char>(1u << (rng() % 8));
    EXPECT_NE(check_one(s, "t.sylt"), "ok");  // the checksum catches every single bit flip
  }
}

// Hand-written skeleton text, mutated.
TEST(ImportFuzz, SkeletonText) {
  const std::string text =
      "0 -1 0 0 0 0.2\n0 -1 0 1 0 0.16\n0 -1 0 2.5 0 0.12\n1 0 0 1.1 0 0.05 1 0 1\n1 0 0.6 1.6 0 0.02\n";
  std::mt19937_64 rng(11);
  for (int i = 0; i < 3000; ++i) check_one(mutate(text, rng), "t.skel");
}

}  // namespace
}  // namespace sylva::import
