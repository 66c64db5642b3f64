#include "stages/import/import_file.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "libs/tree/sylt_format.h"
#include "stages/import/import_error.h"
#include "stages/import/mesh_import.h"
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

// A PLY whose header declares faces ("element face <n>", n > 0) is a mesh.
bool ply_mesh(std::string_view bytes) {
  if (!(bytes.substr(0, 4) == "ply\n" || bytes.substr(0, 5) == "ply\r\n")) return false;
  const std::string_view header = bytes.substr(0, std::min(bytes.find("end_header"), std::size_t(64 * 1024)));
  const std::size_t at = header.find("element face ");
  if (at == std::string_view::npos) return false;
  const std::string_view count = header.substr(at + 13, 1);
  return !count.empty() && count[0] >= '1' && count[0] <= '9';
}

// A JSON object with an "asset" member near its start: a .gltf.
bool gltf_json(std::string_view bytes) {
  std::size_t i = 0;
  if (bytes.substr(0, 3) == "\xEF\xBB\xBF") i = 3;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  return i < bytes.size() && bytes[i] == '{' &&
         bytes.substr(0, 4096).find("\"asset\"") != std::string_view::npos;
}

// Mesh formats by content or name; nullopt when neither says.
std::optional<Format> mesh_format(std::string_view bytes, std::string_view file_name) {
  if (bytes.substr(0, 4) == "glTF" || gltf_json(bytes)) return Format::kGltf;
  if (ply_mesh(bytes)) return Format::kPly;
  if (bytes.substr(0, 18) == "Kaydara FBX Binary") return Format::kFbx;
  static constexpr std::pair<std::string_view, Format> kByName[] = {
      {".gltf", Format::kGltf}, {".glb", Format::kGltf}, {".obj", Format::kObj},
      {".fbx", Format::kFbx},   {".dae", Format::kDae},  {".3ds", Format::k3ds}};
  for (const auto& [ext, f] : kByName)
    if (ends_with(file_name, ext)) return f;
  return std::nullopt;
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
    case Format::kGltf:
      return "gltf";
    case Format::kObj:
      return "obj";
    case Format::kFbx:
      return "fbx";
    case Format::kDae:
      return "dae";
    case Format::k3ds:
      return "3ds";
    case Format::kPly:
      return "ply";
  }
  return "?";
}

bool is_mesh_format(Format f) { return f >= Format::kGltf; }

Format detect_format(std::string_view bytes, std::string_view file_name, bool has_columns,
                     std::string_view source) {
  if (bytes.size() >= sizeof tree::kSyltMagic &&
      std::memcmp(bytes.data(), tree::kSyltMagic, sizeof tree::kSyltMagic) == 0)
    return Format::kSylt;
  if (ends_with(file_name, ".sylt")) return Format::kSylt;
  if (const auto mesh = mesh_format(bytes, file_name)) return *mesh;
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

ImportResult import_file(std::string_view bytes, std::string_view source, const ImportOptions& options) {
  ImportResult result;
  Format& format = result.format;
  if (options.format == "auto") {
    format = detect_format(bytes, source, !options.columns.empty(), source);
  } else {
    bool known = false;
    for (Format f : {Format::kQsm, Format::kTreeQsmText, Format::kSkeletonText, Format::kSylt, Format::kGltf,
                     Format::kObj, Format::kFbx, Format::kDae, Format::k3ds, Format::kPly})
      if (options.format == format_name(f)) {
        format = f;
        known = true;
      }
    if (!known) throw std::invalid_argument("unknown import format '" + options.format + "'");
  }

  switch (format) {
    case Format::kSylt:
      result.tree = tree::decode_sylt(bytes, source);
      return result;
    case Format::kSkeletonText:
      result.tree = parse_skeleton_text(bytes, source);
      return result;
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
      result.tree = qsm_to_tree(table, source, options.qsm);
      return result;
    }
    case Format::kGltf:
    case Format::kObj:
    case Format::kFbx:
    case Format::kDae:
    case Format::k3ds:
    case Format::kPly: {
      MeshImport m =
          import_mesh(std::string(bytes), format_name(format), std::filesystem::path(std::string(source)),
                      source, options.files ? *options.files : fileio::disk_files(), options.mesh);
      result.tree.name =
          std::string(format_name(format)) + " mesh, " + std::to_string(m.facts.triangles) + " triangles";
      result.tree.source = std::move(m.geometry);
      result.warnings = std::move(m.warnings);
      result.mesh = std::move(m.facts);
      return result;
    }
  }
  throw std::logic_error("unreachable");
}

tree::Tree import_tree(std::string_view bytes, std::string_view source, const ImportOptions& options) {
  return import_file(bytes, source, options).tree;
}

}  // namespace sylva::import
