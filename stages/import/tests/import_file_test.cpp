#include "stages/import/import_file.h"

#include <gtest/gtest.h>

#include "libs/tree/sylt_format.h"
#include "stages/import/import_error.h"
#include "stages/import/skeleton_text.h"

namespace sylva::import {
namespace {

Format detect(std::string_view bytes, std::string_view name = "f.txt", bool columns = false) {
  return detect_format(bytes, name, columns, name);
}

std::string detect_error(std::string_view bytes) {
  try {
    detect(bytes);
  } catch (const ImportError& e) {
    return e.what();
  }
  return "";
}

constexpr std::string_view kSkeleton = "0 -1 0 0 0 0.2\n0 -1 0 1 0 0.1\n";

TEST(ImportFile, DetectFormat) {
  const std::string sylt = tree::encode_sylt(parse_skeleton_text(kSkeleton, "s"));
  EXPECT_EQ(detect(sylt, "tree.bin"), Format::kSylt);        // magic wins
  EXPECT_EQ(detect("garbage", "tree.SYLT"), Format::kSylt);  // then the extension
  EXPECT_EQ(detect("ID, parentID", "t.skel"), Format::kSkeletonText);
  EXPECT_EQ(detect("ID, parentID", "t.txt", true), Format::kTreeQsmText);
  EXPECT_EQ(detect("# c\nID, parentID, radius\n1, 2, 3\n"), Format::kQsm);
  EXPECT_EQ(detect("0.3 1 0 0 0 0 0 1 0 2 1 0 1 0\n"), Format::kTreeQsmText);
  EXPECT_EQ(detect(kSkeleton), Format::kSkeletonText);
  EXPECT_EQ(detect_error("1 2 3 4 5 6 7 8 9 10\n"),
            "f.txt:1: cannot detect the format: a headerless row of 10 numbers is neither a TreeQSM "
            "table (12 or more) nor a text skeleton (6 to 9); set the format parameter");
  EXPECT_EQ(detect_error(""), "f.txt:1: empty file: nothing to import");
}

// Issue 15 item 7: point clouds get one answer, not a format guess: by magic (LAS, PLY), by file
// name, or by a headerless row of x y z (+ intensity ...) numbers.
TEST(ImportFile, PointCloudsAreNotSupportedYet) {
  const std::string no =
      "point clouds are not supported yet: reconstruct a QSM cylinder table from the scan first (e.g. "
      "with TreeQSM or SimpleForest) and import that";
  EXPECT_EQ(detect_error(std::string("LASF\x01\x02", 6)), "f.txt:1: " + no);
  EXPECT_EQ(detect_error("ply\nformat ascii 1.0\n"), "f.txt:1: " + no);
  try {
    detect_format("1 2 3\n", "scan.LAZ", false, "scan.LAZ");
    FAIL();
  } catch (const ImportError& e) {
    EXPECT_EQ(std::string(e.what()), "scan.LAZ:1: " + no);
  }
  EXPECT_EQ(detect_error("# scan\n1.5 2 3\n"),
            "f.txt:2: a headerless row of 3 numbers looks like a point cloud (x y z ...); " + no);
}

// .sylt is read with libs/tree and comes back unchanged.
TEST(ImportFile, SyltPassesThrough) {
  tree::Tree t = parse_skeleton_text(kSkeleton, "s");
  t.name = "hand made";
  const tree::Tree back = import_tree(tree::encode_sylt(t), "t.sylt", {});
  EXPECT_EQ(back, t);
}

TEST(ImportFile, SyltErrorsAreTreeFormatErrors) {
  ImportOptions opt;
  opt.format = "sylt";
  EXPECT_THROW(import_tree("not a sylt file", "x.sylt", opt), tree::TreeFormatError);
}

// An explicit format overrides detection.
TEST(ImportFile, ExplicitFormat) {
  ImportOptions opt;
  opt.format = "skeleton_txt";
  EXPECT_EQ(import_tree(kSkeleton, "weird.csv", opt).branches.size(), 1u);
}

// `columns` describes a headerless table; with format qsm (header) it is a contradiction.
TEST(ImportFile, ColumnsWithQsmIsAnError) {
  ImportOptions opt;
  opt.format = "qsm";
  opt.columns = {"radius"};
  EXPECT_THROW(import_tree("radius\n1\n", "t.csv", opt), std::invalid_argument);
}

}  // namespace
}  // namespace sylva::import
