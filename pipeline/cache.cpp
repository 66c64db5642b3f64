#include "pipeline/cache.h"

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

namespace sylva {

namespace fs = std::filesystem;
using nlohmann::json;

std::string ActionResult::to_json() const {
  json j = {{"outputs", json::array()}};
  for (const auto& o : outputs)
    j["outputs"].push_back({{"name", o.name}, {"hash", o.digest.hash}, {"size", o.digest.size}});
  return j.dump() + "\n";
}

std::optional<ActionResult> ActionResult::from_json(const std::string& text) {
  try {
    json j = json::parse(text);
    ActionResult r;
    for (const auto& o : j.at("outputs")) {
      OutputEntry e{o.at("name").get<std::string>(),
                    {o.at("hash").get<std::string>(), o.at("size").get<std::uint64_t>()}};
      if (!is_hex_digest(e.digest.hash)) return std::nullopt;
      r.outputs.push_back(std::move(e));
    }
    return r;
  } catch (const json::exception&) {
    return std::nullopt;  // a damaged action result is a miss, never an error
  }
}

Cache::Cache(FileSystem& fs, fs::path root) : fs_(fs), root_(std::move(root)) {}

fs::path Cache::blob_path(const std::string& hash) const {
  return root_ / "cas" / hash.substr(0, 2) / hash;
}

fs::path Cache::action_path(const std::string& key) const {
  return root_ / "ac" / key.substr(0, 2) / key;
}

std::optional<ActionResult> Cache::lookup(const std::string& key) {
  const fs::path p = action_path(key);
  auto info = fs_.stat(p);
  if (!info) return std::nullopt;
  auto text = fs_.read(p);
  if (!text) return std::nullopt;
  auto result = ActionResult::from_json(*text);
  if (!result) return std::nullopt;
  for (const auto& o : result->outputs) {
    auto st = fs_.stat(blob_path(o.digest.hash));
    if (!st || st->is_dir || st->size != o.digest.size) return std::nullopt;
  }
  // LRU for gc, with relatime's coarseness: a no-op build does not rewrite every entry's inode.
  constexpr std::int64_t kHour = 3600ll * 1000000000;
  if (fs_.now_ns() - info->mtime_ns > kHour) fs_.touch(p);
  return result;
}

void Cache::store_action(const std::string& key, const ActionResult& result) {
  fs_.write_atomic(action_path(key), result.to_json());
}

std::optional<Digest> Cache::put_file(const fs::path& file, std::int64_t* known_at) {
  const std::int64_t now = fs_.now_ns();
  auto d = fs_.digest(file);
  if (!d) return std::nullopt;
  const fs::path dest = blob_path(d->hash);
  // Replacing an existing blob (rather than trusting it) costs nothing and heals a damaged one.
  fs_.set_mtime(file, now - 1);
  fs_.make_read_only(file);
  fs_.make_dirs(dest.parent_path());
  if (!fs_.sync(file) || !fs_.rename(file, dest)) return std::nullopt;
  if (known_at) *known_at = now;
  return d;
}

bool Cache::materialize(const Digest& d, const fs::path& dest, bool verify, std::int64_t* known_at) {
  const fs::path src = blob_path(d.hash);
  const std::int64_t now = fs_.now_ns();
  if (verify) {
    auto actual = fs_.digest(src);
    if (!actual) return false;
    if (!(*actual == d)) {
      fs_.remove(src);  // corrupt: never used, rebuilt by the caller
      return false;
    }
  }
  bool linked = false;
  if (!fs_.link_or_copy(src, dest, &linked)) return false;
  if (!linked) fs_.set_mtime(dest, now - 1);  // a copy is as settled as the blob it copies
  if (known_at) *known_at = now;
  return true;
}

std::unique_ptr<FileLock> Cache::lock_action(const std::string& key) {
  return fs_.lock(root_ / "locks" / key.substr(0, 2) / key);
}

std::unique_ptr<FileLock> Cache::lock_for_build() { return fs_.lock_shared(root_ / "locks" / "gc"); }
std::unique_ptr<FileLock> Cache::lock_for_gc() { return fs_.lock(root_ / "locks" / "gc"); }
std::unique_ptr<FileLock> Cache::try_lock_for_gc() { return fs_.try_lock(root_ / "locks" / "gc"); }

std::uint64_t Cache::blob_bytes() {
  std::uint64_t total = 0;
  for (const auto& fan : fs_.list(root_ / "cas"))
    for (const auto& b : fs_.list(root_ / "cas" / fan))
      if (auto st = fs_.stat(root_ / "cas" / fan / b)) total += st->size;
  return total;
}

fs::path Cache::make_scratch_dir() {
  const fs::path p = unique_temp_path(root_ / "tmp" / "scratch");
  fs_.make_dirs(p);
  return p;
}

CacheStats Cache::stats() {
  CacheStats s;
  for (const auto& fan : fs_.list(root_ / "cas"))
    for (const auto& b : fs_.list(root_ / "cas" / fan)) {
      if (auto st = fs_.stat(root_ / "cas" / fan / b)) {
        ++s.blobs;
        s.blob_bytes += st->size;
      }
    }
  for (const auto& fan : fs_.list(root_ / "ac")) s.actions += fs_.list(root_ / "ac" / fan).size();
  s.tmp_entries = fs_.list(root_ / "tmp").size();
  return s;
}

GcResult Cache::gc(std::uint64_t max_bytes) {
  GcResult r;
  for (const auto& t : fs_.list(root_ / "tmp")) {
    auto age = fs_.age_seconds(root_ / "tmp" / t);
    if (age && *age > 3600 && fs_.remove_all(root_ / "tmp" / t)) ++r.tmp_removed;
  }
  struct Entry {
    fs::path path;
    double age;
    ActionResult result;
  };
  std::vector<Entry> actions;
  for (const auto& fan : fs_.list(root_ / "ac"))
    for (const auto& k : fs_.list(root_ / "ac" / fan)) {
      const fs::path p = root_ / "ac" / fan / k;
      auto text = fs_.read(p);
      auto res = text ? ActionResult::from_json(*text) : std::nullopt;
      if (!res) {  // unreadable results are garbage
        if (fs_.remove(p)) ++r.actions_removed;
        continue;
      }
      actions.push_back({p, fs_.age_seconds(p).value_or(0), std::move(*res)});
    }
  // Most recently used first; keep results while their blobs fit in the budget.
  std::sort(actions.begin(), actions.end(), [](const Entry& a, const Entry& b) {
    return a.age != b.age ? a.age < b.age : a.path < b.path;
  });
  std::set<std::string> live;
  std::uint64_t live_bytes = 0;
  for (const auto& a : actions) {
    std::uint64_t extra = 0;
    for (const auto& o : a.result.outputs)
      if (!live.count(o.digest.hash)) extra += o.digest.size;
    if (max_bytes > 0 && live_bytes + extra > max_bytes) {
      if (fs_.remove(a.path)) ++r.actions_removed;
      continue;
    }
    live_bytes += extra;
    for (const auto& o : a.result.outputs) live.insert(o.digest.hash);
  }
  for (const auto& fan : fs_.list(root_ / "cas"))
    for (const auto& b : fs_.list(root_ / "cas" / fan)) {
      if (live.count(b)) continue;
      const fs::path p = root_ / "cas" / fan / b;
      const auto size = fs_.stat(p).value_or(FileInfo{}).size;
      if (fs_.remove(p)) {
        ++r.blobs_removed;
        r.bytes_freed += size;
      }
    }
  return r;
}

std::uint64_t Cache::verify_all() {
  std::uint64_t removed = 0;
  for (const auto& fan : fs_.list(root_ / "cas"))
    for (const auto& b : fs_.list(root_ / "cas" / fan)) {
      const fs::path p = root_ / "cas" / fan / b;
      auto d = fs_.digest(p);
      if (!d || d->hash != b) {
        if (fs_.remove(p)) ++removed;
      }
    }
  return removed;
}

}  // namespace sylva
