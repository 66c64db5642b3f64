// User-facing errors with a source position, collected and reported together (pbrt's habit):
// a recipe with three mistakes shows all three, each as
//   configs/x.yaml:12:5: error: unknown parameter 'levles' for stage 'lod'; did you mean 'levels'?
// followed, when the source line is known, by that line and a caret under the column.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

struct SourceLoc {
  SourceLoc() = default;
  SourceLoc(std::string file, int line = 0, int col = 0)
      : file_(std::make_shared<const std::string>(std::move(file))), line(line), col(col) {}
  // Locations in one file share its name (a 10,000-node recipe has ~50,000 of them).
  SourceLoc(std::shared_ptr<const std::string> file, int line, int col)
      : file_(std::move(file)), line(line), col(col) {}

  // As the user named it (relative paths stay relative); "" if unknown.
  const std::string& file() const {
    static const std::string kNone;
    return file_ ? *file_ : kNone;
  }
  const std::shared_ptr<const std::string>& shared_file() const { return file_; }

 private:
  std::shared_ptr<const std::string> file_;

 public:
  int line = 0;                // 1-based; 0 = unknown
  int col = 0;                 // 1-based; 0 = unknown
  std::string prefix() const;  // "file:line:col" (omits unknown parts)
};

struct Diagnostic {
  SourceLoc loc;
  std::string message;
  std::string source_line;  // the text of loc.line, when known (for the caret display)

  std::string str() const;     // "file:line:col: error: message"
  std::string pretty() const;  // str() + source line + caret, for terminals and logs
};

// Keeps at most `max_kept` diagnostics (a 50 MB recipe of broken nodes must not print 10^6
// errors or hold them); further errors are only counted, and str()/pretty() end with a line
// saying how many were not shown.
class Diagnostics {
 public:
  static constexpr std::size_t kDefaultMaxKept = 100;
  explicit Diagnostics(std::size_t max_kept = kDefaultMaxKept) : max_kept_(max_kept) {}
  void error(SourceLoc loc, std::string message, std::string source_line = {});
  bool empty() const { return list_.empty(); }
  std::size_t size() const { return list_.size() + dropped_; }  // every error, kept or not
  bool full() const { return list_.size() >= max_kept_; }       // callers may stop looking
  const std::vector<Diagnostic>& all() const { return list_; }
  std::string str() const;     // every kept diagnostic's str(), one per line
  std::string pretty() const;  // every kept diagnostic's pretty()

 private:
  std::string dropped_line() const;
  std::size_t max_kept_;
  std::vector<Diagnostic> list_;
  std::size_t dropped_ = 0;
};

// Bytes from a recipe or any file, made safe to print: control bytes (C0 except tab, DEL, and
// UTF-8-encoded C1 controls such as CSI) become \xNN, so no terminal escape, bell or NUL ever
// reaches the terminal; other bytes are kept.
std::string escape_bytes(std::string_view text);
// escape_bytes() of at most the first `max_bytes` bytes of `text` (cut at a UTF-8 character
// boundary), with "..." appended when cut: how messages quote values they did not expect.
std::string excerpt(std::string_view text, std::size_t max_bytes = 40);

// Levenshtein distance (for did-you-mean suggestions).
std::size_t edit_distance(std::string_view a, std::string_view b);
// "; did you mean 'x'?" for the closest candidate within a distance of max(2, |word|/3), else "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace sylva
