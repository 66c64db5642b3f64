#include "pipeline/diagnostic.h"

#include <algorithm>

namespace sylva {

std::string SourceLoc::prefix() const {
  std::string s = file();
  if (line > 0) {
    s += ":" + std::to_string(line);
    if (col > 0) s += ":" + std::to_string(col);
  }
  return s;
}

std::string Diagnostic::str() const {
  const std::string p = loc.prefix();
  return (p.empty() ? "" : p + ": ") + "error: " + message;
}

std::string Diagnostic::pretty() const {
  std::string s = str();
  if (!source_line.empty() && loc.col > 0) {
    s += "\n  " + source_line + "\n  ";
    // Keep tabs so the caret lines up under tab-indented text.
    for (int i = 0; i < loc.col - 1 && i < static_cast<int>(source_line.size()); ++i)
      s += source_line[i] == '\t' ? '\t' : ' ';
    s += "^";
  }
  return s;
}

void Diagnostics::error(SourceLoc loc, std::string message, std::string source_line) {
  list_.push_back({std::move(loc), std::move(message), std::move(source_line)});
}

std::string Diagnostics::str() const {
  std::string s;
  for (const auto& d : list_) s += d.str() + "\n";
  return s;
}

std::string Diagnostics::pretty() const {
  std::string s;
  for (const auto& d : list_) s += d.pretty() + "\n";
  return s;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
  const std::string* best = nullptr;
  std::size_t best_d = limit + 1;
  for (const auto& c : candidates) {  // first of equally close candidates wins: deterministic
    std::size_t d = edit_distance(word, c);
    // A word that is a prefix of a candidate (`fov_y` for `fov_y_deg`) is a likely slip.
    if (word.size() >= 3 && c.size() > word.size() && c.compare(0, word.size(), word) == 0) d = std::min(d, limit);
    if (d < best_d) {
      best_d = d;
      best = &c;
    }
  }
  return best ? "; did you mean '" + *best + "'?" : "";
}

}  // namespace sylva
