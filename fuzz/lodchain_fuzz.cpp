// libFuzzer target: the lod artifact's readers of outside data (libs/lodchain, docs/stages/lod.md
// "Outputs"). Contract: parse_lod_chain returns a chain or throws LodChainFormatError with a
// message, and a parsed chain written back parses to the same chain; parse_level_file (a level
// file, chain_gltf.h) returns or throws ChainGltfError with a message.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_check.h"
#include "libs/lodchain/chain_gltf.h"
#include "libs/lodchain/lod_chain.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sylva;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)lodchain::parse_level_file(text, "fuzz/lod0.gltf",
                                     [](const std::string&, lodchain::LevelResource) {});
  } catch (const lodchain::ChainGltfError& e) {
    fuzz::expect_message(e.what());
  } catch (const std::exception& e) {
    fuzz::fail(std::string("parse_level_file threw an undocumented error: ") + e.what());
  }
  lodchain::LodChain chain;
  try {
    chain = lodchain::parse_lod_chain(text, "fuzz/lod.json");
  } catch (const lodchain::LodChainFormatError& e) {
    fuzz::expect_message(e.what());
    return 0;
  } catch (const std::exception& e) {
    fuzz::fail(std::string("parse_lod_chain threw an undocumented error: ") + e.what());
  }
  try {
    if (!(lodchain::parse_lod_chain(lodchain::write_lod_chain(chain), "fuzz/again.json") == chain))
      fuzz::fail("a parsed lod.json written back parses to another chain");
  } catch (const std::exception& e) {
    fuzz::fail(std::string("a parsed lod.json written back does not parse: ") + e.what());
  }
  return 0;
}
