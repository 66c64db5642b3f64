// The one error type of the import parsers: a problem in the input, located at a line.
//
// Every parser in stages/import reports bad input by throwing ImportError; the stage adapter
// turns it into a sylva::StageError unchanged. what() is the full user-facing text
//   "<source>:<line>: <message>"
// where <source> is the file as named to the parser, <line> is 1-based, and <message> names the
// field (column) where one is relevant: "field 10 (radius): radius must be > 0, got -0.5".
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace sylva::import {

class ImportError : public std::runtime_error {
 public:
  ImportError(std::string_view source, int line, std::string_view message)
      : std::runtime_error(std::string(source) + ":" + std::to_string(line) + ": " + std::string(message)),
        line_(line),
        message_(message) {}

  int line() const { return line_; }                       // 1-based
  const std::string& message() const { return message_; }  // without "<source>:<line>: "

 private:
  int line_;
  std::string message_;
};

}  // namespace sylva::import
