// libFuzzer target: the .sylt reader (libs/tree/sylt_format.h, docs/tree-format.md). Contract:
// decode_sylt returns a tree or throws TreeFormatError with a message; a decoded tree encodes
// again (the reader accepts nothing the writer refuses) and decodes to the same bytes.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "libs/tree/sylt_format.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sylva;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  tree::Tree t;
  try {
    t = tree::decode_sylt(bytes, "fuzz.sylt");
  } catch (const tree::TreeFormatError& e) {
    fuzz::expect_message(e.what());
    return 0;
  } catch (const std::exception& e) {
    fuzz::fail(std::string("decode_sylt threw an undocumented error: ") + e.what());
  }
  try {
    const std::string again = tree::encode_sylt(t);
    if (tree::encode_sylt(tree::decode_sylt(again, "fuzz-again.sylt")) != again)
      fuzz::fail("encode(decode(encode(t))) differs from encode(t)");
  } catch (const std::exception& e) {
    fuzz::fail(std::string("a decoded tree does not encode/decode again: ") + e.what());
  }
  return 0;
}
