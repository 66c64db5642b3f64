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

namespace {

bool is_continuation(unsigned char c) { return (c & 0xC0) == 0x80; }

void append_escaped(std::string& out, std::string_view text) {
  static const char kHex[] = "0123456789abcdef";
  auto hex = [&](unsigned char c) {
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 15];
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if ((c < 0x20 && c != '\t') || c == 0x7F) {
      hex(c);
    } else if (c == 0xC2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
               static_cast<unsigned char>(text[i + 1]) <= 0x9F) {  // U+0080..U+009F: C1 controls
      hex(c);
      hex(static_cast<unsigned char>(text[++i]));
    } else {
      out += static_cast<char>(c);
    }
  }
}

// Display columns of escaped text: one per character (UTF-8 continuation bytes add none).
std::size_t columns(std::string_view escaped) {
  std::size_t n = 0;
  for (char c : escaped) n += is_continuation(static_cast<unsigned char>(c)) ? 0 : 1;
  return n;
}

std::size_t char_start(std::string_view s, std::size_t i) {  // i moved back to a character start
  while (i > 0 && i < s.size() && is_continuation(static_cast<unsigned char>(s[i]))) --i;
  return i;
}

// The source line shown under a diagnostic: at most this many bytes on either side of the
// column (a minified one-line recipe, or a secret on a long line, is not printed whole).
constexpr std::size_t kContextBytes = 60;

}  // namespace

std::string escape_bytes(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  append_escaped(out, text);
  return out;
}

std::string excerpt(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return escape_bytes(text);
  return escape_bytes(text.substr(0, char_start(text, max_bytes))) + "...";
}

std::string Diagnostic::str() const {
  const std::string p = loc.prefix();
  return escape_bytes(p.empty() ? "" : p + ": ") + "error: " + escape_bytes(message);
}

std::string Diagnostic::pretty() const {
  std::string s = str();
  if (!source_line.empty() && loc.col > 0) {
    const std::string_view line = source_line;
    const std::size_t col = std::min(static_cast<std::size_t>(loc.col - 1), line.size());
    const std::size_t from = col > kContextBytes ? char_start(line, col - kContextBytes) : 0;
    const std::size_t to =
        line.size() - col > kContextBytes ? char_start(line, col + kContextBytes) : line.size();
    std::string before = from > 0 ? "..." : "";
    append_escaped(before, line.substr(from, col - from));
    std::string shown = before;
    append_escaped(shown, line.substr(col, to - col));
    if (to < line.size()) shown += "...";
    s += "\n  " + shown + "\n  ";
    // Keep tabs so the caret lines up under tab-indented text.
    const std::size_t width = columns(before);
    for (std::size_t i = 0, seen = 0; seen < width && i < before.size(); ++i) {
      if (is_continuation(static_cast<unsigned char>(before[i]))) continue;
      s += before[i] == '\t' ? '\t' : ' ';
      ++seen;
    }
    s += "^";
  }
  return s;
}

void Diagnostics::error(SourceLoc loc, std::string message, std::string source_line) {
  if (full()) {
    ++dropped_;
    return;
  }
  list_.push_back({std::move(loc), std::move(message), std::move(source_line)});
}

std::string Diagnostics::dropped_line() const {
  if (dropped_ == 0) return "";
  return "sylva: " + std::to_string(dropped_) + " more error" + (dropped_ == 1 ? "" : "s") +
         " not shown (at most " + std::to_string(max_kept_) + " are; raise it with --limit errors=N)\n";
}

std::string Diagnostics::str() const {
  std::string s;
  for (const auto& d : list_) s += d.str() + "\n";
  return s + dropped_line();
}

std::string Diagnostics::pretty() const {
  std::string s;
  for (const auto& d : list_) s += d.pretty() + "\n";
  return s + dropped_line();
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
    if (word.size() >= 3 && c.size() > word.size() && c.compare(0, word.size(), word) == 0)
      d = std::min(d, limit);
    if (d < best_d) {
      best_d = d;
      best = &c;
    }
  }
  return best ? "; did you mean '" + *best + "'?" : "";
}

}  // namespace sylva
