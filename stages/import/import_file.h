// Bytes of one file -> tree: format detection and dispatch to the parsers. Pure (no I/O);
// the stage adapter (import_stage.cpp) reads the file and writes the result.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "libs/tree/tree.h"
#include "stages/import/qsm_to_tree.h"

namespace sylva::import {

enum class Format {
  kQsm,           // QSM cylinder table with a header line (CSV, TSV, ...)
  kTreeQsmText,   // headerless TreeQSM cylinder text (column order: TableOptions::columns)
  kSkeletonText,  // sylva text skeleton (skeleton_text.h)
  kSylt,          // native .sylt (libs/tree/sylt_format.h)
};

// The `format` parameter's spelling: "qsm", "treeqsm_txt", "skeleton_txt", "sylt".
const char* format_name(Format f);

// Resolves format "auto" from the bytes and the file name, first rule that matches:
//   1. the bytes start with the .sylt magic, or the name ends in ".sylt"  -> sylt;
//   2. the name ends in ".skel"                                         -> skeleton_txt;
//   3. `has_columns` (the columns parameter is set)                     -> treeqsm_txt;
//   4. the first line that is not blank or a '#' comment:
//        has a field that is not a number (a header)                    -> qsm;
//        12 or more numeric fields                                      -> treeqsm_txt;
//        6 to 9 numeric fields                                          -> skeleton_txt.
// Throws ImportError for an empty file or a first line that fits none of these.
Format detect_format(std::string_view bytes, std::string_view file_name, bool has_columns,
                     std::string_view source);

struct ImportOptions {
  std::string format = "auto";       // "auto" or a format_name()
  std::vector<std::string> columns;  // headerless column names (treeqsm_txt)
  QsmToTreeOptions qsm;              // frame/unit conversion; QSM formats only
};

// The tree in `bytes`. `source` names the file in messages (and its extension feeds auto
// detection). Throws ImportError (text formats: "<source>:<line>: ...") or
// tree::TreeFormatError (.sylt: "<source>: byte <n>: ..."); std::invalid_argument for options
// that contradict each other (columns with format qsm). The result passes validate_tree.
tree::Tree import_tree(std::string_view bytes, std::string_view source, const ImportOptions& options);

}  // namespace sylva::import
