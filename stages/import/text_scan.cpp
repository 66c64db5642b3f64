#include "stages/import/text_scan.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <system_error>

namespace sylva::import::text {

LineReader::LineReader(std::string_view text) : text_(text) {
  if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
}

bool LineReader::next(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = text_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line = text_.substr(pos_, stop - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end == std::string_view::npos ? text_.size() : end + 1;
  ++line_;
  return true;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool is_blank_or_comment(std::string_view line) {
  const std::string_view t = trim(line);
  return t.empty() || t.front() == '#';
}

Separator detect_separator(std::string_view line) {
  if (line.find('\t') != std::string_view::npos) return Separator::kTab;
  if (line.find(',') != std::string_view::npos) return Separator::kComma;
  if (line.find(';') != std::string_view::npos) return Separator::kSemicolon;
  return Separator::kWhitespace;
}

const char* separator_name(Separator sep) {
  switch (sep) {
    case Separator::kTab:
      return "tab";
    case Separator::kComma:
      return "comma";
    case Separator::kSemicolon:
      return "semicolon";
    case Separator::kWhitespace:
      return "whitespace";
  }
  return "?";
}

void split_fields(std::string_view line, Separator sep, std::vector<std::string_view>& out) {
  out.clear();
  if (sep == Separator::kWhitespace) {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
      if (i > start) out.push_back(line.substr(start, i - start));
    }
    return;
  }
  const char c = sep == Separator::kTab ? '\t' : sep == Separator::kComma ? ',' : ';';
  std::size_t start = 0;
  while (true) {
    const std::size_t end = line.find(c, start);
    std::string_view f =
        trim(line.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
    if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = f.substr(1, f.size() - 2);
    out.push_back(f);
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
}

NumberStatus parse_real(std::string_view s, double& out) {
  if (s.empty()) return NumberStatus::kEmpty;
  if (s.front() == '+') s.remove_prefix(1);
  if (s.empty() || s.front() == '+') return NumberStatus::kNotNumber;
  double v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  // from_chars reports out-of-range values (1e999) as an error: they are not finite either.
  if (ec == std::errc::result_out_of_range && ptr == s.data() + s.size()) return NumberStatus::kNotFinite;
  if (ec != std::errc() || ptr != s.data() + s.size()) return NumberStatus::kNotNumber;
  if (!std::isfinite(v)) return NumberStatus::kNotFinite;
  out = v;
  return NumberStatus::kOk;
}

NumberStatus parse_integer(std::string_view s, std::int64_t& out) {
  double v = 0;
  const NumberStatus st = parse_real(s, v);
  if (st != NumberStatus::kOk) return st;
  constexpr double kMax = 9007199254740992.0;  // 2^53: every integer below is exact
  if (v != std::floor(v) || std::abs(v) > kMax) return NumberStatus::kNotNumber;
  out = static_cast<std::int64_t>(v);
  return NumberStatus::kOk;
}

std::string quoted(std::string_view s) {
  constexpr std::size_t kMaxShown = 40;
  std::string out = "'";
  std::size_t shown = 0;
  for (const char ch : s) {
    if (shown == kMaxShown) {
      out += "...";
      break;
    }
    const auto u = static_cast<unsigned char>(ch);
    if (u >= 0x20 && u < 0x7f) {
      out += ch;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", u);
      out += buf;
    }
    ++shown;
  }
  return out + "'";
}

std::string format_real(double v) {
  char buf[64];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, ptr) : std::string("nan");
}

}  // namespace sylva::import::text
