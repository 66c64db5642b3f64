// The content-addressable store (Bazel's CAS): output bytes named by their SHA-256. The other
// seam of the engine's cache: the build loop stores a node's outputs and makes them appear in
// out/ only through this interface. The local implementation is Cache (pipeline/cache.h);
// tests use tests/support/fake_cache.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/digest.h"

namespace sylva {

class BlobStore {
 public:
  virtual ~BlobStore() = default;

  // Moves `file` (a stage's finished output, on the engine's FileSystem) into the store, named
  // by its digest: hashed first unless `known` (its digest, computed while it was written) is
  // given. The file is gone afterwards. `known_at` (if given) receives the file-system clock
  // read before the blob's content was fixed (DigestCache's racy rule). `durable`: the blob
  // survives a power loss when this returns; without, only after make_durable() names it.
  // nullopt (and `error`) on failure.
  virtual std::optional<Digest> put_file(const std::filesystem::path& file, std::int64_t* known_at = nullptr,
                                         bool durable = true, std::string* error = nullptr,
                                         const std::optional<Digest>& known = std::nullopt) = 0;

  // Makes `dest` hold blob `d` atomically (a hard link where possible: the bytes stored once).
  // With `verify` the blob is hashed first, and one that does not match its digest is deleted
  // and false returned (the caller rebuilds). `known_at` receives the clock read before the
  // content was verified (for DigestCache::record). False (and `error`) on failure.
  virtual bool materialize(const Digest& d, const std::filesystem::path& dest, bool verify = true,
                           std::int64_t* known_at = nullptr, std::string* error = nullptr) = 0;

  // Makes the blobs `digests` (stored without `durable`) survive a power loss: their bytes and
  // their names. False (and `error`) on failure.
  virtual bool make_durable(const std::vector<Digest>& digests, std::string* error = nullptr) = 0;
};

}  // namespace sylva
