// Small text helpers shared by the import parsers: lines, separators, fields, numbers.
//
// Everything works on string_views into the caller's buffer (no copies per row) and never
// throws; parsers decide what a problem means and raise ImportError with the location.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace sylva::import::text {

// Physical lines of `text`, numbered from 1. A trailing '\r' (CRLF files) and a UTF-8 byte
// order mark at the start of the first line are removed.
class LineReader {
 public:
  explicit LineReader(std::string_view text);
  // The next line, false at the end of the text.
  bool next(std::string_view& line);
  int line_number() const { return line_; }  // of the line next() returned last

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_ = 0;
};

std::string_view trim(std::string_view s);  // spaces and tabs at both ends
// True for a line that is empty, only blanks, or whose first non-blank character is '#'.
bool is_blank_or_comment(std::string_view line);

enum class Separator { kTab, kComma, kSemicolon, kWhitespace };

// The separator of a table, from its first significant line: a tab if the line has one, else
// ',' if it has one, else ';' if it has one, else runs of blanks.
Separator detect_separator(std::string_view line);
const char* separator_name(Separator sep);

// Splits `line` into `out` (cleared first). With a character separator every field is trimmed
// and one pair of surrounding double quotes is removed ("ID" -> ID); "a,,b" has an empty field.
// With kWhitespace fields are the runs of non-blank characters.
void split_fields(std::string_view line, Separator sep, std::vector<std::string_view>& out);

enum class NumberStatus { kOk, kEmpty, kNotNumber, kNotFinite };

// A decimal real ("1", "-2.5", "3e-4", "+1"); the whole field must be the number.
NumberStatus parse_real(std::string_view s, double& out);
// A real with an integral value within ±2^53 ("12", "12.0", "1e+05": R writes big ids so).
// kNotNumber also for a finite non-integral value.
NumberStatus parse_integer(std::string_view s, std::int64_t& out);

// `s` for an error message: in single quotes, bytes outside printable ASCII as \xNN, cut to
// 40 characters with "...".
std::string quoted(std::string_view s);

// Shortest decimal text that reads back to exactly `v` ("0.25", "1", "-3e-07").
std::string format_real(double v);

}  // namespace sylva::import::text
