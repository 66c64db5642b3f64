// An in-memory ActionCache and BlobStore (pipeline/action_cache.h, blob_store.h) for tests of the
// build loop's use of the cache seams, and a model of a cache that is not the local disk (a
// shared remote one): results and blobs live in maps, a stored output's bytes are read through
// the engine's FileSystem and a published one is written through it. Every call is recorded in
// order. Thread-safe.
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "pipeline/action_cache.h"
#include "pipeline/blob_store.h"
#include "pipeline/cache.h"
#include "pipeline/filesystem.h"

namespace sylva::test {

class FakeCache final : public ActionCache, public BlobStore {
 public:
  explicit FakeCache(FileSystem& fs) : fs_(fs) {}

  std::map<std::string, ActionResult> results;  // key -> result
  std::map<std::string, std::string> blobs;     // hash -> bytes
  // "lookup <key>", "store <key>", "put <hash>", "materialize <hash>", "durable blobs <n>",
  // "durable results <n>" (keys and hashes cut to 8 characters).
  std::vector<std::string> calls;

  std::optional<ActionResult> lookup(const std::string& key,
                                     const std::vector<std::string>& outputs = {}) override {
    std::lock_guard l(mu_);
    calls.push_back("lookup " + key.substr(0, 8));
    auto it = results.find(key);
    if (it == results.end()) return std::nullopt;
    for (const auto& o : it->second.outputs)
      if (!output_name_declared(o.name, outputs) || !blobs.count(o.digest.hash)) return std::nullopt;
    return it->second;
  }
  bool store(const std::string& key, const ActionResult& result, bool = true,
             std::string* = nullptr) override {
    std::lock_guard l(mu_);
    calls.push_back("store " + key.substr(0, 8));
    results[key] = result;
    return true;
  }
  bool make_durable(const std::vector<std::string>& keys, std::string* = nullptr) override {
    std::lock_guard l(mu_);
    calls.push_back("durable results " + std::to_string(keys.size()));
    return true;
  }
  std::optional<Digest> put_file(const std::filesystem::path& file, std::int64_t* known_at = nullptr,
                                 bool = true, std::string* error = nullptr,
                                 const std::optional<Digest>& = std::nullopt) override {
    auto bytes = fs_.read(file, error);
    if (!bytes) return std::nullopt;
    const Digest d = digest_bytes(*bytes);
    fs_.remove(file);
    std::lock_guard l(mu_);
    calls.push_back("put " + d.hash.substr(0, 8));
    blobs[d.hash] = std::move(*bytes);
    if (known_at) *known_at = fs_.now_ns();
    return d;
  }
  bool materialize(const Digest& d, const std::filesystem::path& dest, bool verify = true,
                   std::int64_t* known_at = nullptr, std::string* error = nullptr) override {
    std::string bytes;
    {
      std::lock_guard l(mu_);
      calls.push_back("materialize " + d.hash.substr(0, 8));
      auto it = blobs.find(d.hash);
      if (it == blobs.end()) {
        if (error) *error = "no such blob";
        return false;
      }
      if (verify && digest_bytes(it->second) != d) {  // corrupt: never used, rebuilt by the caller
        blobs.erase(it);
        if (error) *error = "blob " + d.hash.substr(0, 12) + " is corrupt (deleted)";
        return false;
      }
      bytes = it->second;
    }
    if (known_at) *known_at = fs_.now_ns();
    return fs_.write_atomic(dest, bytes, /*durable=*/false, error);
  }
  bool make_durable(const std::vector<Digest>& digests, std::string* = nullptr) override {
    std::lock_guard l(mu_);
    calls.push_back("durable blobs " + std::to_string(digests.size()));
    return true;
  }

  // The calls whose text starts with `prefix`.
  std::size_t count(const std::string& prefix) {
    std::lock_guard l(mu_);
    std::size_t n = 0;
    for (const auto& c : calls) n += c.rfind(prefix, 0) == 0 ? 1 : 0;
    return n;
  }

 private:
  FileSystem& fs_;
  std::mutex mu_;
};

}  // namespace sylva::test
