#include "stages/import/qsm_table.h"

#include <gtest/gtest.h>

#include "stages/import/import_error.h"

namespace sylva::import {
namespace {

// Parses `text` expecting an ImportError; returns its full message ("" if none was thrown).
std::string error_of(std::string_view text, const TableOptions& options = {}) {
  try {
    parse_cylinder_table(text, "t.csv", options);
  } catch (const ImportError& e) {
    return e.what();
  }
  return "";
}

// A three-cylinder SimpleForest table: stem of two cylinders, one lateral.
constexpr std::string_view kSimpleForest =
    "ID, parentID, startX, startY, startZ, endX, endY, endZ, radius, branchOrder, branchID\n"
    "0, -1, 0, 0, 0, 0, 0, 1, 0.2, 0, 0\n"
    "1, 0, 0, 0, 1, 0, 0, 2, 0.1, 0, 0\n"
    "2, 0, 0, 0, 1, 1, 0, 1, 0.05, 1, 1\n";

TEST(QsmTable, NormalizeColumnName) {
  EXPECT_EQ(normalize_column_name(" start_X "), "startx");
  EXPECT_EQ(normalize_column_name("parentID"), "parentid");
  EXPECT_EQ(normalize_column_name("radius (m)"), "radius");
  EXPECT_EQ(normalize_column_name("UnmodRadius (m)"), "unmodradius");
  EXPECT_EQ(normalize_column_name("length [m]"), "length");
  EXPECT_EQ(normalize_column_name("cyl_ID"), "cylid");
}

// SimpleForest: 0-based ids, parent -1 = root, comma+space separated, end points.
TEST(QsmTable, SimpleForestHeader) {
  const CylinderTable t = parse_cylinder_table(kSimpleForest, "t.csv");
  EXPECT_EQ(t.variant, "simpleforest");
  ASSERT_EQ(t.cylinders.size(), 3u);
  EXPECT_EQ(t.root, 0);
  EXPECT_TRUE(t.has_branch);
  EXPECT_TRUE(t.has_order);
  EXPECT_EQ(t.cylinders[2].parent, 0);
  EXPECT_EQ(t.cylinders[2].order, 1);
  EXPECT_EQ(t.cylinders[2].branch, 1);
  EXPECT_EQ(t.cylinders[2].line, 4);
  EXPECT_EQ(t.cylinders[1].end, (tree::Vec3{0, 0, 2}));
  EXPECT_EQ(t.cylinders[1].radius, 0.1);
}

// Windows line ends, a byte order mark and trailing blank lines change nothing.
TEST(QsmTable, CrlfAndBom) {
  std::string crlf = "\xEF\xBB\xBF";
  for (const char ch : kSimpleForest) {
    if (ch == '\n') crlf += '\r';
    crlf += ch;
  }
  crlf += "\r\n\r\n";
  const CylinderTable a = parse_cylinder_table(kSimpleForest, "t.csv");
  const CylinderTable b = parse_cylinder_table(crlf, "t.csv");
  ASSERT_EQ(b.cylinders.size(), a.cylinders.size());
  for (std::size_t i = 0; i < a.cylinders.size(); ++i) {
    EXPECT_EQ(b.cylinders[i].end, a.cylinders[i].end);
    EXPECT_EQ(b.cylinders[i].parent, a.cylinders[i].parent);
    EXPECT_EQ(b.cylinders[i].line, a.cylinders[i].line);
  }
}

// TreeQSM with a header and no id column: rows are cylinders 1..n, parent 0 = none, the end
// point is start + normalised axis * length; '#' comment lines are skipped.
TEST(QsmTable, TreeQsmHeaderWithAxis) {
  const CylinderTable t = parse_cylinder_table(
      "# TreeQSM table\n"
      "radius\tlength\tstart_x\tstart_y\tstart_z\taxis_x\taxis_y\taxis_"
      "z\tparent\textension\tbranch\tBranchOrder\n"
      "0.2\t2\t1\t1\t0\t0\t0\t2\t0\t2\t1\t0\n"
      "0.1\t1\t1\t1\t2\t0.6\t0\t0.8\t1\t0\t1\t0\n",
      "t.tsv");
  EXPECT_EQ(t.variant, "treeqsm");
  ASSERT_EQ(t.cylinders.size(), 2u);
  EXPECT_EQ(t.cylinders[0].id, 1);
  EXPECT_EQ(t.cylinders[0].end, (tree::Vec3{1, 1, 2}));  // axis (0,0,2) normalised
  EXPECT_EQ(t.cylinders[1].parent, 0);
  EXPECT_NEAR(t.cylinders[1].end.x, 1.6, 1e-12);
  EXPECT_NEAR(t.cylinders[1].end.z, 2.8, 1e-12);
  EXPECT_EQ(t.cylinders[1].line, 4);
}

// TreeQSM's save_model_text 1.1 header: 13 names above 17 columns ("start_point" and
// "axis_direction" cover three columns each), units in parentheses.
TEST(QsmTable, TreeQsmVectorHeaderNames) {
  const CylinderTable t = parse_cylinder_table(
      "radius (m)\tlength (m)\tstart_point\taxis_direction\tparent\textension\tbranch\tbranch_order\t"
      "position_in_branch\tmad\tSurfCov\tadded\tUnmodRadius (m)\n"
      "0.3\t1\t0\t0\t0\t0\t0\t1\t0\t2\t1\t0\t1\t0\t1\t0\t0.3\n"
      "0.2\t1\t0\t0\t1\t0\t0\t1\t1\t0\t1\t0\t2\t0\t1\t0\t0.2\n",
      "cylinder_tree.txt");
  ASSERT_EQ(t.cylinders.size(), 2u);
  EXPECT_EQ(t.cylinders[1].start, (tree::Vec3{0, 0, 1}));
  EXPECT_EQ(t.cylinders[1].end, (tree::Vec3{0, 0, 2}));
  EXPECT_EQ(t.root, 0);
}

// aRchi's QSM table: cyl_ID / parent_ID / axis_ID / branching_order / radius_cyl; 1-based ids
// with parent 0 as the root marker.
TEST(QsmTable, ArchiHeader) {
  const CylinderTable t = parse_cylinder_table(
      "\"startX\",\"startY\",\"startZ\",\"endX\",\"endY\",\"endZ\",\"cyl_ID\",\"parent_ID\","
      "\"extension_ID\",\"radius_cyl\",\"length\",\"volume\",\"axis_ID\",\"segment_ID\",\"node_ID\","
      "\"branching_order\"\n"
      "0,0,0,0,0,1,1,0,2,0.2,1,0.1,1,1,0,0\n"
      "0,0,1,0,0,2,2,1,0,0.1,1,0.03,1,1,0,0\n",
      "archi.csv");
  EXPECT_EQ(t.variant, "archi");
  EXPECT_EQ(t.root, 0);
  EXPECT_EQ(t.cylinders[1].parent, 0);
  EXPECT_EQ(t.cylinders[0].radius, 0.2);
}

// Rows may list children before parents; ids need not be contiguous.
TEST(QsmTable, ParentsMayComeLater) {
  const CylinderTable t = parse_cylinder_table(
      "id,parent,startx,starty,startz,endx,endy,endz,radius\n"
      "20,10,0,0,1,0,0,2,0.1\n"
      "10,-1,0,0,0,0,0,1,0.2\n",
      "t.csv");
  EXPECT_EQ(t.variant, "generic");
  EXPECT_EQ(t.root, 1);
  EXPECT_EQ(t.cylinders[0].parent, 1);
  EXPECT_FALSE(t.has_branch);
  EXPECT_FALSE(t.has_order);
}

// Headerless TreeQSM text: the default column order covers the first 12 of 14, 15 or 17
// fields; "# Branch data" ends the cylinder section of a combined dump.
TEST(QsmTable, HeaderlessDefaultOrder) {
  TableOptions opt;
  opt.headerless = true;
  const CylinderTable t = parse_cylinder_table(
      "# Cylinder data\n"
      "0.3 1 0 0 0 0 0 1 0 2 1 0 1 0\n"
      "0.2 1.414 0 0 1 0.707 0 0.707 1 0 1 0 2 0\n"
      "0.1 1 0 0 1 0 1 0 1 0 2 1 1 0\n"
      "# Branch data\n"
      "0 0 491.8 3.414 0 1.333\n",
      "qsm.txt", opt);
  EXPECT_EQ(t.variant, "treeqsm_txt");
  ASSERT_EQ(t.cylinders.size(), 3u);
  EXPECT_EQ(t.cylinders[2].parent, 0);
  EXPECT_EQ(t.cylinders[2].branch, 2);
  EXPECT_EQ(t.cylinders[2].order, 1);
}

// Issue 15 item 7: a real TreeQSM export that puts added and UnmodRadius before branch and
// order. With the order only assumed, the error says so and names the `columns` parameter.
TEST(QsmTable, HeaderlessOtherOrderNamesTheColumnsParameter) {
  TableOptions opt;
  opt.headerless = true;
  EXPECT_EQ(
      error_of("0.3 1 0 0 0 0 0 1 0 2 1 0.31 0 0\n", opt),
      "t.csv:1: field 12 (branch_order): expected an integer, got '0.31'; the table has no header, so "
      "TreeQSM's column order (radius length start_x start_y start_z axis_x axis_y axis_z parent extension "
      "branch branch_order) was assumed: if this export orders its columns differently, list them in the "
      "import stage's `columns` parameter");
  // With the order declared, the same table reads.
  opt.columns = {"radius", "length", "start_x",   "start_y", "start_z",      "axis_x", "axis_y",
                 "axis_z", "parent", "extension", "added",   "unmod_radius", "branch", "branch_order"};
  EXPECT_EQ(parse_cylinder_table("0.3 1 0 0 0 0 0 1 0 2 1 0.31 0 0\n", "t.csv", opt).cylinders.size(), 1u);
}

// A declared column order (the `columns` parameter) reads any headerless layout.
TEST(QsmTable, HeaderlessDeclaredColumns) {
  TableOptions opt;
  opt.columns = {"id", "parent", "start", "end", "radius", "ignored"};
  const CylinderTable t = parse_cylinder_table(
      "1 0 0 0 0 0 0 1 0.2 7\n"
      "2 1 0 0 1 0 0 2 0.1 7\n",
      "q.txt", opt);
  ASSERT_EQ(t.cylinders.size(), 2u);
  EXPECT_EQ(t.cylinders[1].end, (tree::Vec3{0, 0, 2}));
  EXPECT_EQ(t.cylinders[1].parent, 0);
}

TEST(QsmTable, ErrorEmptyFile) {
  EXPECT_EQ(error_of(""), "t.csv:1: empty file: no header and no cylinder rows");
  EXPECT_EQ(error_of("# only a comment\n\n"), "t.csv:2: empty file: no header and no cylinder rows");
}

TEST(QsmTable, ErrorHeaderOnly) {
  EXPECT_EQ(error_of("ID, parentID, startX, startY, startZ, endX, endY, endZ, radius\n"),
            "t.csv:1: header but no cylinder rows");
}

TEST(QsmTable, ErrorUnknownHeader) {
  EXPECT_EQ(error_of("x, y, z, intensity\n1, 2, 3, 4\n"),
            "t.csv:1: unknown header: none of its 4 names is a recognised QSM column (such as "
            "radius, startX, endX, parentID; see docs/stages/import.md)");
}

TEST(QsmTable, ErrorMissingColumns) {
  EXPECT_EQ(error_of("ID, parentID, startX, startY, startZ, endX, endY, endZ\n"),
            "t.csv:1: header has no radius column");
  EXPECT_EQ(error_of("ID, parentID, startX, startY, endX, endY, endZ, radius\n"),
            "t.csv:1: header has startX, startY but no start z column");
  EXPECT_EQ(error_of("ID, parentID, startX, startY, startZ, radius, length\n"),
            "t.csv:1: header has neither end point columns (endX endY endZ) nor axis columns "
            "with a length (axis_x axis_y axis_z length)");
  EXPECT_EQ(error_of("ID, startX, startY, startZ, endX, endY, endZ, radius\n"),
            "t.csv:1: header has no parent column (parentID, parent or parent_ID)");
  EXPECT_EQ(error_of("ID, parentID, startX, startY, startZ, endX, endY, endZ, radius, Radius\n"),
            "t.csv:1: header: fields 9 (radius) and 10 (Radius) name the same column");
}

TEST(QsmTable, ErrorHeaderlessWithoutFormat) {
  EXPECT_EQ(error_of("0.3 1 0 0 0 0 0 1 0 2 1 0 1 0\n"),
            "t.csv:1: expected a header line naming the columns, found a row of numbers; for "
            "TreeQSM's headerless text use format treeqsm_txt (and the columns parameter if its "
            "column order differs)");
}

TEST(QsmTable, ErrorTruncatedAndLongRows) {
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 1, 0, 0, 2, 0\n"),
            "t.csv:5: truncated row: 6 fields, expected 11");
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 1, 0, 0, 2, 0, 0, 3, 0.1, 0, 0, 9\n"),
            "t.csv:5: row has 12 fields, expected 11");
}

TEST(QsmTable, ErrorNaNAndGarbage) {
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 1, 0, 0, 2, nan, 0, 3, 0.1, 0, 0\n"),
            "t.csv:5: field 6 (endX): not a finite number: 'nan'");
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 1, 0, 0, 2, 0, 0, 3, NA, 0, 0\n"),
            "t.csv:5: field 9 (radius): expected a number, got 'NA'");
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 1, 0, 0, 2, 0, 0, 3, , 0, 0\n"),
            "t.csv:5: field 9 (radius): empty, expected a number");
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 1.5, 0, 0, 2, 0, 0, 3, 0.1, 0, 0\n"),
            "t.csv:5: field 2 (parentID): expected an integer, got '1.5'");
}

TEST(QsmTable, ErrorRadius) {
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 1, 0, 0, 2, 0, 0, 3, -0.5, 0, 0\n"),
            "t.csv:5: field 9 (radius): radius must be > 0, got -0.5");
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 1, 0, 0, 2, 0, 0, 3, 0, 0, 0\n"),
            "t.csv:5: field 9 (radius): radius must be > 0, got 0");
}

TEST(QsmTable, ErrorAxisAndLength) {
  const std::string head = "radius,length,start_x,start_y,start_z,axis_x,axis_y,axis_z,parent\n";
  EXPECT_EQ(error_of(head + "0.1,-1,0,0,0,0,0,1,0\n"),
            "t.csv:2: field 2 (length): length must be >= 0, got -1");
  EXPECT_EQ(error_of(head + "0.1,1,0,0,0,0,0,0,0\n"), "t.csv:2: field 6 (axis_x): axis is the zero vector");
}

TEST(QsmTable, ErrorMissingParent) {
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 57, 0, 0, 2, 0, 0, 3, 0.1, 0, 0\n"),
            "t.csv:5: field 2 (parentID): parent 57 is not the id of any cylinder");
}

TEST(QsmTable, ErrorDuplicateId) {
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "1, 0, 0, 0, 2, 0, 0, 3, 0.1, 0, 0\n"),
            "t.csv:5: field 1 (ID): duplicate cylinder id 1 (also on line 3)");
}

TEST(QsmTable, ErrorSecondRoot) {
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, -1, 5, 0, 0, 5, 0, 1, 0.1, 0, 0\n"),
            "t.csv:5: field 2 (parentID): cylinder 3 is a second root (the first is cylinder 0 "
            "on line 2); a table must describe one tree");
}

// 3 -> 4 -> 5 -> 3 never reaches the root; the message walks the cycle from its first row.
TEST(QsmTable, ErrorCycle) {
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "4, 3, 0, 0, 2, 0, 0, 3, 0.1, 0, 0\n"
                                                  "3, 5, 0, 0, 2, 0, 0, 3, 0.1, 0, 0\n"
                                                  "5, 4, 0, 0, 2, 0, 0, 3, 0.1, 0, 0\n"),
            "t.csv:5: field 2 (parentID): cylinder 4 is in a parent cycle: 4 -> 3 -> 5 -> 4");
  EXPECT_EQ(error_of(std::string(kSimpleForest) + "3, 3, 0, 0, 2, 0, 0, 3, 0.1, 0, 0\n"),
            "t.csv:5: field 2 (parentID): cylinder 3 is its own parent");
}

// With no root at all every cylinder is on or above a cycle.
TEST(QsmTable, ErrorNoRoot) {
  EXPECT_EQ(error_of("ID,parentID,startX,startY,startZ,endX,endY,endZ,radius\n"
                     "0,1,0,0,0,0,0,1,0.2\n"
                     "1,0,0,0,1,0,0,2,0.1\n"),
            "t.csv:2: field 2 (parentID): cylinder 0 is in a parent cycle: 0 -> 1 -> 0");
}

TEST(QsmTable, ErrorHeaderlessLooksLikeHeader) {
  TableOptions opt;
  opt.headerless = true;
  EXPECT_EQ(error_of("radius length start_x\n", opt),
            "t.csv:1: this line looks like a header, but the table was declared headerless "
            "(format treeqsm_txt or the columns parameter); use format qsm to read the header");
  EXPECT_EQ(error_of("0.3 1 0 0 0 0 0 1 0 2\n", opt),
            "t.csv:1: truncated row: 10 fields, a headerless TreeQSM table has at least 12 "
            "(radius length start_x start_y start_z axis_x axis_y axis_z parent extension branch "
            "branch_order)");
}

TEST(QsmTable, ErrorDeclaredColumnsIncomplete) {
  TableOptions opt;
  opt.columns = {"id", "parent", "start", "end"};
  EXPECT_EQ(error_of("1 0 0 0 0 0 0 1\n", opt), "t.csv:1: columns parameter has no radius column");
}

}  // namespace
}  // namespace sylva::import
