// QSM cylinder tables: the parsing core (text in -> CylinderTable or ImportError).
//
// A quantitative structure model (QSM) describes a laser-scanned tree as cylinders, one per
// row: radius, start point, end point (or unit axis + length), parent cylinder, and usually a
// branch id and branch order. The column set and conventions differ between tools
// (SimpleForest/CompuTree, rTwig, aRchi, TreeQSM); docs/stages/import.md lists every column
// name recognised here and the rules below.
//
// This file does no file I/O and knows nothing of the tree model: it turns text into a checked
// table in the file's own frame and units (QSM files are Z up, metres). qsm_to_tree.h turns the
// table into a tree.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "libs/tree/vec3.h"

namespace sylva::import {

struct Cylinder {
  tree::Vec3 start;          // file frame and units
  tree::Vec3 end;            // given, or start + normalised axis * length
  double radius = 0;         // > 0
  std::int64_t id = 0;       // as written in the id column, or the 1-based row number
  std::int32_t parent = -1;  // index into CylinderTable::cylinders, -1 for the root
  std::int64_t branch = 0;   // branch column value (0 when the table has none)
  std::int64_t order = 0;    // branch order column value (0 when the table has none)
  std::int32_t line = 0;     // 1-based line of the row in the source
};

struct CylinderTable {
  // Which convention the header matched, for messages and docs: "simpleforest" (also rTwig's
  // and CompuTree's exports), "archi", "treeqsm" (a TreeQSM table with a header), "generic"
  // (recognised names in another combination) or "treeqsm_txt" (headerless).
  std::string variant;
  bool has_branch = false;          // a branch id column was present
  bool has_order = false;           // a branch order column was present
  std::vector<Cylinder> cylinders;  // in file order; >= 1
  std::int32_t root = -1;           // index of the one cylinder without a parent
};

struct TableOptions {
  // Headerless table (TreeQSM's text export): the first significant line is already data.
  bool headerless = false;
  // Column names of a headerless table, in order, using the header vocabulary (vector names
  // such as "start" stand for 3 columns). Empty: TreeQSM's order, which every TreeQSM version
  // shares for its first 12 columns: radius length start(3) axis(3) parent extension branch
  // branch_order; further columns are ignored.
  std::vector<std::string> columns;
};

// Parses and checks a cylinder table. `source` names the text in error messages. Checks:
// required columns present; every row has exactly the header's field count; every used field
// a finite number (ids, parents, branches and orders integral); radius > 0; length >= 0; a
// non-zero axis when the end point is given as axis + length; ids unique; every parent an
// existing id (or the root marker: -1, or 0 when no cylinder has id 0); exactly one root; no
// parent cycles. Throws ImportError at the first problem.
//
// Cost: O(rows x columns) time; the table holds one Cylinder per row.
CylinderTable parse_cylinder_table(std::string_view text, std::string_view source,
                                   const TableOptions& options = {});

// The normalised form of a column name used for matching: ASCII lower case, a trailing unit in
// parentheses or brackets removed ("radius (m)"), then every character that is not a letter or
// digit removed. "start_X" -> "startx", "parentID" -> "parentid", "UnmodRadius (m)" ->
// "unmodradius".
std::string normalize_column_name(std::string_view name);

}  // namespace sylva::import
