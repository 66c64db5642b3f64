// What every sylva fuzz target asserts (fuzz/README.md): a parser given any bytes either returns
// a value or throws its documented error type with a non-empty message. Anything else - another
// exception, a crash, a sanitizer report, a hang or a huge allocation - is a finding.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace sylva::fuzz {

// Aborts (libFuzzer then saves the input as a crash) with `why`.
[[noreturn]] inline void fail(std::string_view why) {
  std::fprintf(stderr, "fuzz target contract broken: %.*s\n", static_cast<int>(why.size()), why.data());
  std::abort();
}

// Checks a documented error's message: never empty.
inline void expect_message(const char* what) {
  if (what == nullptr || *what == '\0') fail("documented error thrown with an empty message");
}

}  // namespace sylva::fuzz
