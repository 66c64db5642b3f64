// The action cache (Bazel's vocabulary): action key -> the outputs that action produced. One seam
// of the engine's cache: the build loop looks results up and stores them only through this
// interface, so a cache elsewhere (a remote HTTP cache in front of the local one) plugs in here.
// The local implementation is Cache (pipeline/cache.h); tests use tests/support/fake_cache.h.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "pipeline/digest.h"

namespace sylva {

struct OutputEntry {
  std::string name;  // file name within the node's output directory
  Digest digest;
  friend bool operator==(const OutputEntry&, const OutputEntry&) = default;
};

struct ActionResult {
  std::vector<OutputEntry> outputs;  // sorted by name
  // The entry stored under `key`.
  std::string to_json(const std::string& key) const;
  // The entry's outputs if it is well formed and names `key` (Cache's rules, pipeline/cache.h);
  // else nullopt. `why` (optional) says what is wrong.
  static std::optional<ActionResult> from_json(const std::string& text, const std::string& key,
                                               std::string* why = nullptr);
};

class ActionCache {
 public:
  virtual ~ActionCache() = default;
  // The result for `key` if one is stored, it is valid for `key` (it names its own key, lists at
  // least one output, every name a plain file name matching one of `outputs`, the stage's
  // declared fnmatch patterns; empty = any name) and every blob it names is present with its
  // recorded size. Anything else is a miss: a crafted or damaged entry is never trusted.
  virtual std::optional<ActionResult> lookup(const std::string& key,
                                             const std::vector<std::string>& outputs = {}) = 0;
  // Stores the result for `key`. With `durable` it survives a power loss when this returns;
  // without, only after make_durable() names the key. False (and `error`) if it could not be
  // stored. The blobs it names must already be durable (BlobStore::make_durable).
  virtual bool store(const std::string& key, const ActionResult& result, bool durable = true,
                     std::string* error = nullptr) = 0;
  // Makes the results stored (not durably) under `keys` survive a power loss. False (and
  // `error`) on failure.
  virtual bool make_durable(const std::vector<std::string>& keys, std::string* error = nullptr) = 0;
};

}  // namespace sylva
