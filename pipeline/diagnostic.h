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
  SourceLoc(std::shared_ptr<const std::string> file, int line, int col) : file_(std::move(file)), line(line), col(col) {}

  // As the user named it (relative paths stay relative); "" if unknown.
  const std::string& file() const {
    static const std::string kNone;
    return file_ ? *file_ : kNone;
  }
  const std::shared_ptr<const std::string>& shared_file() const { return file_; }

 private:
  std::shared_ptr<const std::string> file_;

 public:
  int line = 0;  // 1-based; 0 = unknown
  int col = 0;   // 1-based; 0 = unknown
  std::string prefix() const;  // "file:line:col" (omits unknown parts)
};

struct Diagnostic {
  SourceLoc loc;
  std::string message;
  std::string source_line;  // the text of loc.line, when known (for the caret display)

  std::string str() const;     // "file:line:col: error: message"
  std::string pretty() const;  // str() + source line + caret, for terminals and logs
};

class Diagnostics {
 public:
  void error(SourceLoc loc, std::string message, std::string source_line = {});
  bool empty() const { return list_.empty(); }
  std::size_t size() const { return list_.size(); }
  const std::vector<Diagnostic>& all() const { return list_; }
  std::string str() const;     // every diagnostic's str(), one per line
  std::string pretty() const;  // every diagnostic's pretty()

 private:
  std::vector<Diagnostic> list_;
};

// Levenshtein distance (for did-you-mean suggestions).
std::size_t edit_distance(std::string_view a, std::string_view b);
// "; did you mean 'x'?" for the closest candidate within a distance of max(2, |word|/3), else "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace sylva
