#include "stages/import/import_file.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <stdexcept>

#include "libs/tree/sylt_format.h"
#include "stages/import/import_error.h"
#include "stages/import/qsm_table.h"
#include "stages/import/skeleton_text.h"
#include "stages/import/text_scan.h"

namespace sylva::import {

namespace {

bool ends_with(std::string_view s, std::string_view suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(
      suffix.begin(), suffix.end(), s.end() - static_cast<std::ptrdiff_t>(suffix.size()), [](char a, char b) {
        return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
      });
}

// Point clouds (LiDAR and photogrammetry scans) are a different kind of input: a tree has to be
// reconstructed from them (a QSM), which sylva does not do yet. Recognised by their magic bytes
// (LAS "LASF", PLY "ply") or file name, they get that answer instead of a format guess.
bool point_cloud(std::string_view bytes, std::string_view file_name) {
  if (bytes.substr(0, 4) == "LASF") return true;
  if (bytes.substr(0, 4) == "ply\n" || bytes.substr(0, 5) == "ply\r\n") return true;
  for (std::string_view ext : {".las", ".laz", ".ply", ".pcd", ".e57", ".xyz", ".pts"})
    if (ends_with(file_name, ext)) return true;
  return false;
}

constexpr const char* kNoPointClouds =
    "point clouds are not supported yet: reconstruct a QSM cylinder table from the scan first (e.g. "
    "with TreeQSM or SimpleForest) and import that";

}  // namespace

const char* format_name(Format f) {
  switch (f) {
    case Format::kQsm:
      return "qsm";
    case Format::kTreeQsmText:
      return "treeqsm_txt";
    case Format::kSkeletonText:
      return "skeleton_txt";
    case Format::kSylt:
      return "sylt";
  }
  return "?";
}

Format detect_format(std::string_view bytes, std::string_view file_name, bool has_columns,
                     std::string_view source) {
  if (bytes.size() >= sizeof tree::kSyltMagic &&
      std::memcmp(bytes.data(), tree::kSyltMagic, sizeof tree::kSyltMagic) == 0)
    return Format::kSylt;
  if (ends_with(file_name, ".sylt")) return Format::kSylt;
  if (point_cloud(bytes, file_name)) throw ImportError(source, 1, kNoPointClouds);
  if (ends_with(file_name, ".skel")) return Format::kSkeletonText;
  if (has_columns) return Format::kTreeQsmText;

  text::LineReader reader(bytes);
  std::string_view line;
  while (reader.next(line)) {
    if (text::is_blank_or_comment(line)) continue;
    std::vector<std::string_view> fields;
    text::split_fields(line, text::detect_separator(line), fields);
    double v;
    const auto numeric = std::count_if(fields.begin(), fields.end(), [&](std::string_view f) {
      return text::parse_real(f, v) == text::NumberStatus::kOk;
    });
    if (static_cast<std::size_t>(numeric) < fields.size()) return Format::kQsm;
    if (fields.size() >= 12) return Format::kTreeQsmText;
    if (fields.size() >= 6 && fields.size() <= 9) return Format::kSkeletonText;
    if (fields.size() >= 3 && fields.size() <= 5)
      throw ImportError(source, reader.line_number(),
                        "a headerless row of " + std::to_string(fields.size()) +
                            " numbers looks like a point cloud (x y z ...); " + kNoPointClouds);
    throw ImportError(source, reader.line_number(),
                      "cannot detect the format: a headerless row of " + std::to_string(fields.size()) +
                          " numbers is neither a TreeQSM table (12 or more) nor a text skeleton "
                          "(6 to 9); set the format parameter");
  }
  throw ImportError(source, std::max(1, reader.line_number()), "empty file: nothing to import");
}

tree::Tree import_tree(std::string_view bytes, std::string_view source, const ImportOptions& options) {
  Format format;
  if (options.format == "auto")
    format = detect_format(bytes, source, !options.columns.empty(), source);
  else if (options.format == "qsm")
    format = Format::kQsm;
  else if (options.format == "treeqsm_txt")
    format = Format::kTreeQsmText;
  else if (options.format == "skeleton_txt")
    format = Format::kSkeletonText;
  else if (options.format == "sylt")
    format = Format::kSylt;
  else
    throw std::invalid_argument("unknown import format '" + options.format + "'");

  switch (format) {
    case Format::kSylt:
      return tree::decode_sylt(bytes, source);
    case Format::kSkeletonText:
      return parse_skeleton_text(bytes, source);
    case Format::kQsm:
    case Format::kTreeQsmText: {
      TableOptions table_options;
      table_options.headerless = format == Format::kTreeQsmText;
      if (format == Format::kQsm && !options.columns.empty())
        throw std::invalid_argument(
            "the columns parameter names the columns of a headerless table: use it with format "
            "treeqsm_txt (or auto), not qsm, whose header names the columns");
      table_options.columns = options.columns;
      const CylinderTable table = parse_cylinder_table(bytes, source, table_options);
      return qsm_to_tree(table, source, options.qsm);
    }
  }
  throw std::logic_error("unreachable");
}

}  // namespace sylva::import
