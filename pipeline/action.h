// Actions: everything that can change a node's outputs, and the key that names them.
//
// key = SHA-256 of the canonical text of: a global salt (kActionSalt, bumped to disown results
// a bug poisoned), the stage name and implementation version, the canonical parameters (file
// and directory parameters contribute their content digest, not their path), the digests of
// every upstream output file in `needs` order, and the digests of every file parameter.
// Upstream node names and file paths are recorded for `sylva explain` but are NOT hashed:
// renaming a node or moving a preset with the same content is a cache hit.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/digest.h"
#include "pipeline/filesystem.h"
#include "pipeline/recipe.h"

namespace sylva {

inline constexpr const char* kActionSalt = "sylva-action-v1";

struct ActionInput {
  std::string node;                                   // not hashed
  std::string type;                                   // hashed
  std::vector<std::pair<std::string, Digest>> files;  // name -> digest, sorted by name; hashed
};

struct ActionFile {
  std::string path;  // not hashed
  Digest digest;     // hashed (for a directory: digest of its listing of relative paths + digests)
};

struct ActionRecord {
  std::string stage;
  int version = 0;
  std::map<std::string, std::string> params;  // name -> canonical value (files: "sha256:<hash>")
  std::vector<ActionInput> inputs;
  std::map<std::string, ActionFile> files;  // parameter name -> file

  std::string key_text() const;  // the exact text hashed
  std::string key() const;       // hex SHA-256 of key_text()
  std::string to_json() const;   // everything, for out/<recipe>/.sylva/<node>.json
  static std::optional<ActionRecord> from_json(const std::string& text);
};

// Why `now` differs from `before`, one human sentence per difference, in a fixed order:
// stage/version, parameters, inputs, files. Empty if the keys are equal.
std::vector<std::string> explain_difference(const ActionRecord& before, const ActionRecord& now);

}  // namespace sylva
