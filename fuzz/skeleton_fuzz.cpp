// libFuzzer target: the text skeleton format (docs/formats-skeleton.md). Contract:
// parse_skeleton_text returns a valid tree or throws ImportError with a message; a parsed tree
// written back with format_skeleton_text parses again.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "libs/tree/tree.h"
#include "stages/import/import_error.h"
#include "stages/import/skeleton_text.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sylva;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  tree::Tree t;
  try {
    t = import::parse_skeleton_text(text, "fuzz.skel");
  } catch (const import::ImportError& e) {
    fuzz::expect_message(e.what());
    return 0;
  } catch (const std::exception& e) {
    fuzz::fail(std::string("parse_skeleton_text threw an undocumented error: ") + e.what());
  }
  if (!tree::validate_tree(t).empty()) fuzz::fail("parse_skeleton_text returned an invalid tree");
  try {
    (void)import::parse_skeleton_text(import::format_skeleton_text(t), "fuzz-again.skel");
  } catch (const std::exception& e) {
    fuzz::fail(std::string("a written skeleton does not parse again: ") + e.what());
  }
  return 0;
}
