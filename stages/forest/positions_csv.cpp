// A spreadsheet's CSV: cells trimmed of blanks, no quoting (names and numbers need none). Every
// error names the file and line, and quotes the offending cell safely (a binary file given by
// mistake must not put raw bytes into a terminal).
#include "stages/forest/positions_csv.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace sylva::forest {

namespace {

// The line's comma-separated cells, each trimmed of spaces, tabs and '\r'; a trailing comma
// ends with an empty cell.
std::vector<std::string> split_cells(const std::string& l) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream ls(l);
  while (std::getline(ls, cell, ',')) {
    const auto b = cell.find_first_not_of(" \t\r"), e = cell.find_last_not_of(" \t\r");
    cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  if (!l.empty() && l.back() == ',') cells.emplace_back();
  return cells;
}

// A cell quoted in a message: at most 40 characters, bytes outside printable ASCII as \xHH.
std::string quoted(const std::string& c) {
  std::string q;
  for (std::size_t i = 0; i < c.size() && i < 40; ++i) {
    const auto u = static_cast<unsigned char>(c[i]);
    if (u >= 0x20 && u < 0x7f) {
      q += c[i];
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", unsigned(u));
      q += hex;
    }
  }
  return "'" + q + (c.size() > 40 ? "...'" : "'");
}

// The reader's state: where it is (for messages) and which column holds what (-1: none yet).
struct CsvReader {
  const std::vector<std::string>& names;
  const std::string& source;
  int lineno = 0;
  int col_species = -1, col_x = -1, col_z = -1, col_yaw = -1, col_scale = -1;
  std::size_t columns = 0;

  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument(source + (lineno > 0 ? ":" + std::to_string(lineno) : std::string()) + ": " +
                                what);
  }

  // The header line: every cell names a known column, once; species, x and z are required.
  void read_header(const std::vector<std::string>& cells) {
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::string& h = cells[c];
      int* slot = h == "species"   ? &col_species
                  : h == "x"       ? &col_x
                  : h == "z"       ? &col_z
                  : h == "yaw_deg" ? &col_yaw
                  : h == "scale"   ? &col_scale
                                   : nullptr;
      if (!slot) fail("unknown column " + quoted(h) + " (expected species, x, z, yaw_deg, scale)");
      if (*slot >= 0) fail("column " + quoted(h) + " appears twice");
      *slot = int(c);
    }
    if (col_species < 0 || col_x < 0 || col_z < 0) fail("the header must name the columns species, x and z");
    columns = cells.size();
  }

  // Column `col`'s cell as a finite decimal number (no hexadecimal, nothing after it).
  double number(const std::vector<std::string>& cells, int col, const char* what) const {
    const std::string& c = cells[std::size_t(col)];
    char* end = nullptr;
    const double v = std::strtod(c.c_str(), &end);
    if (c.empty() || *end != '\0' || end != c.c_str() + c.size() || !std::isfinite(v) ||
        c.find_first_of("xX") != std::string::npos)
      fail(std::string(what) + " " + quoted(c) + " is not a number");
    return v;
  }

  // A tree's line, after the header.
  ExplicitTree read_tree(const std::vector<std::string>& cells) const {
    if (cells.size() != columns)
      fail("expected " + std::to_string(columns) + " values, got " + std::to_string(cells.size()));
    ExplicitTree t;
    t.line = lineno;
    const auto it = std::find(names.begin(), names.end(), cells[std::size_t(col_species)]);
    if (it == names.end()) fail("unknown species " + quoted(cells[std::size_t(col_species)]));
    t.species = std::uint32_t(it - names.begin());
    t.position = {number(cells, col_x, "x"), number(cells, col_z, "z")};
    if (col_yaw >= 0) {
      t.yaw_deg = std::fmod(number(cells, col_yaw, "yaw_deg"), 360.0);
      if (t.yaw_deg < 0) t.yaw_deg += 360;
    }
    if (col_scale >= 0) {
      t.scale = number(cells, col_scale, "scale");
      // The range of the species' scale_x/y/z parameters.
      if (!(t.scale >= 0.001 && t.scale <= 1000)) fail("scale must lie in 0.001..1000");
    }
    return t;
  }
};

}  // namespace

std::vector<ExplicitTree> parse_positions_csv(const std::string& text, const std::vector<std::string>& names,
                                              const std::string& source) {
  std::vector<ExplicitTree> out;
  CsvReader r{names, source};
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    ++r.lineno;
    // A UTF-8 byte order mark (spreadsheets write one) is not part of the first column's name.
    if (r.lineno == 1 && line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#')
      continue;
    const std::vector<std::string> cells = split_cells(line);
    if (r.col_species < 0)
      r.read_header(cells);
    else
      out.push_back(r.read_tree(cells));
  }
  if (r.col_species < 0) {
    r.lineno = 0;
    r.fail("no header line (species,x,z[,yaw_deg][,scale]): the file is empty or holds only comments");
  }
  return out;
}

}  // namespace sylva::forest
