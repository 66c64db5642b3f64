// libFuzzer target: QSM cylinder tables (stages/import/qsm_table.h, docs/stages/import.md):
// with a header (format qsm), TreeQSM's headerless text (treeqsm_txt) and format auto. The first
// input byte picks the format, the rest is the file. Contract: import_tree returns a valid tree
// (validate_tree has nothing to say) or throws ImportError with a message (MeshError when format
// auto finds a mesh's magic, e.g. "glTF"; TreeFormatError for the .sylt magic).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "libs/tree/sylt_format.h"
#include "libs/tree/tree.h"
#include "stages/import/import_error.h"
#include "stages/import/import_file.h"
#include "stages/import/mesh_options.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace sylva;
  if (size == 0) return 0;
  static const char* const kFormats[] = {"qsm", "treeqsm_txt", "auto"};
  import::ImportOptions options;
  options.format = kFormats[data[0] % 3];
  const std::string_view bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    const tree::Tree t = import::import_tree(bytes, "fuzz.csv", options);
    if (!tree::validate_tree(t).empty()) fuzz::fail("import_tree returned an invalid tree");
  } catch (const import::ImportError& e) {
    fuzz::expect_message(e.what());
  } catch (const import::MeshError& e) {
    fuzz::expect_message(e.what());  // format auto on bytes that start with a mesh's magic
  } catch (const tree::TreeFormatError& e) {
    fuzz::expect_message(e.what());  // format auto on bytes that start with the .sylt magic
  } catch (const std::exception& e) {
    fuzz::fail(std::string("import_tree threw an undocumented error: ") + e.what());
  }
  return 0;
}
