#include "pipeline/cache.h"

#include <fnmatch.h>

#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "pipeline/recipe.h"

namespace sylva {

namespace fs = std::filesystem;
using nlohmann::json;

std::string ActionResult::to_json(const std::string& key) const {
  json j = {{"key", key}, {"outputs", json::array()}};
  for (const auto& o : outputs)
    j["outputs"].push_back({{"name", o.name}, {"hash", o.digest.hash}, {"size", o.digest.size}});
  return j.dump() + "\n";
}

std::optional<ActionResult> ActionResult::from_json(const std::string& text, const std::string& key,
                                                    std::string* why) {
  auto bad = [&](std::string reason) -> std::optional<ActionResult> {
    if (why) *why = std::move(reason);
    return std::nullopt;
  };
  try {
    json j = json::parse(text);
    if (!j.is_object() || !j.contains("key") || j.at("key") != key)
      return bad("it does not name its own key");
    ActionResult r;
    for (const auto& o : j.at("outputs")) {
      OutputEntry e{o.at("name").get<std::string>(),
                    {o.at("hash").get<std::string>(), o.at("size").get<std::uint64_t>()}};
      // The same rule as a stage's output names: never a path, never "." or "..".
      if (!is_valid_name(e.name)) return bad("it names an invalid output file");
      if (!is_hex_digest(e.digest.hash)) return bad("it names an invalid digest");
      if (!r.outputs.empty() && !(r.outputs.back().name < e.name))
        return bad("its outputs are not sorted and unique");
      r.outputs.push_back(std::move(e));
    }
    if (r.outputs.empty()) return bad("it lists no outputs");
    return r;
  } catch (const json::exception&) {
    return bad("it is not a valid action result");  // a damaged action result is a miss, never an error
  }
}

bool output_name_declared(const std::string& name, const std::vector<std::string>& patterns) {
  if (patterns.empty()) return true;
  for (const auto& p : patterns)
    if (fnmatch(p.c_str(), name.c_str(), 0) == 0) return true;
  return false;
}

Cache::Cache(FileSystem& fs, fs::path root) : fs_(fs), root_(std::move(root)) {}

fs::path Cache::blob_path(const std::string& hash) const { return root_ / "cas" / hash.substr(0, 2) / hash; }

fs::path Cache::action_path(const std::string& key) const { return root_ / "ac" / key.substr(0, 2) / key; }

std::optional<ActionResult> Cache::lookup(const std::string& key, const std::vector<std::string>& outputs) {
  const fs::path p = action_path(key);
  auto info = fs_.stat(p);
  if (!info || info->is_dir || info->is_other) return std::nullopt;
  auto text = fs_.read(p, nullptr, kMaxActionBytes);
  if (!text) return std::nullopt;
  auto result = ActionResult::from_json(*text, key);
  if (!result) return std::nullopt;
  for (const auto& o : result->outputs) {
    if (!output_name_declared(o.name, outputs)) return std::nullopt;  // another stage's entry
    auto st = fs_.stat(blob_path(o.digest.hash));
    if (!st || st->is_dir || st->is_other || st->size != o.digest.size) return std::nullopt;
  }
  // LRU for gc, with relatime's coarseness: a no-op build does not rewrite every entry's inode.
  constexpr std::int64_t kHour = 3600ll * 1000000000;
  if (fs_.now_ns() - info->mtime_ns > kHour) fs_.touch(p);
  return result;
}

bool Cache::store(const std::string& key, const ActionResult& result, bool durable, std::string* error) {
  const fs::path p = action_path(key);
  if (make_parent(p, error) && fs_.write_atomic(p, result.to_json(key), durable, error)) return true;
  if (error) *error = p.string() + ": " + *error;
  return false;
}

bool Cache::make_parent(const fs::path& file, std::string* error) {
  const fs::path dir = file.parent_path();
  if (fs_.stat(dir)) return true;
  std::vector<fs::path> missing;  // dir and each missing ancestor, innermost first
  for (fs::path d = dir; !d.empty() && d != d.parent_path() && !fs_.stat(d); d = d.parent_path())
    missing.push_back(d);
  if (!fs_.make_dirs(dir, error)) return false;
  std::lock_guard l(dirs_mu_);
  new_dirs_.insert(missing.begin(), missing.end());
  return true;
}

bool Cache::sync_files(const std::vector<fs::path>& files, std::string* error) {
  if (files.empty()) return true;
  if (files.size() > kSyncEachMaxFiles) return fs_.sync_fs(root_, error);
  // fsync of every file, then of every directory holding one or holding a directory this cache
  // created (an fsync of a directory makes the names renamed or made in it durable), each once.
  std::set<fs::path> dirs;
  for (const auto& f : files) {
    if (!fs_.sync(f, error)) {
      if (error) *error = f.string() + ": " + *error;
      return false;
    }
    dirs.insert(f.parent_path());
  }
  {
    std::lock_guard l(dirs_mu_);
    for (const auto& d : new_dirs_) dirs.insert(d.parent_path());
    new_dirs_.clear();
  }
  for (const auto& d : dirs)
    if (!fs_.sync(d, error)) {
      if (error) *error = d.string() + ": " + *error;
      return false;
    }
  return true;
}

bool Cache::make_durable(const std::vector<std::string>& keys, std::string* error) {
  std::vector<fs::path> files;
  for (const auto& k : keys) files.push_back(action_path(k));
  return sync_files(files, error);
}

bool Cache::make_durable(const std::vector<Digest>& digests, std::string* error) {
  std::set<fs::path> unique;
  for (const auto& d : digests) unique.insert(blob_path(d.hash));
  return sync_files({unique.begin(), unique.end()}, error);
}

std::optional<Digest> Cache::put_file(const fs::path& file, std::int64_t* known_at, bool durable,
                                      std::string* error, const std::optional<Digest>& known) {
  const std::int64_t now = fs_.now_ns();
  auto d = known ? known : fs_.digest(file, error);
  if (!d) return std::nullopt;
  const fs::path dest = blob_path(d->hash);
  // A file that is the blob itself (an input passed on with StageContext::link_output, a hard
  // link of it) is stored already; its mtime must not move under the published links of it.
  if (known) {
    auto a = fs_.stat(file), b = fs_.stat(dest);
    if (a && b && !b->is_dir && a->ino == b->ino && a->dev == b->dev && b->size == known->size) {
      fs_.remove(file);
      if (durable && !make_durable(std::vector<Digest>{*d}, error)) return std::nullopt;
      if (known_at) *known_at = now;
      return d;
    }
  }
  // Replacing an existing blob (rather than trusting it) costs nothing and heals a damaged one.
  fs_.set_mtime(file, now - 1);
  fs_.make_read_only(file);
  if (!make_parent(dest, error)) return std::nullopt;
  if (!fs_.rename(file, dest, error)) return std::nullopt;
  if (durable && !make_durable(std::vector<Digest>{*d}, error)) return std::nullopt;
  if (known_at) *known_at = now;
  return d;
}

bool Cache::materialize(const Digest& d, const fs::path& dest, bool verify, std::int64_t* known_at,
                        std::string* error) {
  const fs::path src = blob_path(d.hash);
  const std::int64_t now = fs_.now_ns();
  if (verify) {
    auto actual = fs_.digest(src, error);
    if (!actual) return false;
    if (!(*actual == d)) {
      fs_.remove(src);  // corrupt: never used, rebuilt by the caller
      if (error) *error = "blob " + d.hash.substr(0, 12) + " is corrupt (deleted)";
      return false;
    }
  }
  bool linked = false;
  if (!fs_.link_or_copy(src, dest, &linked, error)) return false;
  if (!linked) fs_.set_mtime(dest, now - 1);  // a copy is as settled as the blob it copies
  if (known_at) *known_at = now;
  return true;
}

std::unique_ptr<FileLock> Cache::lock_action(const std::string& key) {
  return fs_.lock(root_ / "locks" / key.substr(0, 2) / key);
}

namespace {
constexpr std::string_view kCacheTag =
    "Signature: 8a477f597d28d172789f06886806bc55\n"
    "# This directory is a sylva cache (content-addressed build outputs); `sylva clean --all`\n"
    "# deletes it. See https://bford.info/cachedir/\n";
}  // namespace

void Cache::mark() {
  const fs::path tag = root_ / "CACHEDIR.TAG";
  if (!fs_.stat(tag)) fs_.write_atomic(tag, kCacheTag, /*durable=*/false);  // best effort
}

bool Cache::is_cache(FileSystem& fs, const fs::path& dir) {
  if (auto tag = fs.read(dir / "CACHEDIR.TAG", nullptr, 4096); tag && *tag == kCacheTag) return true;
  const auto names = fs.list(dir);
  if (std::find(names.begin(), names.end(), "locks") == names.end()) return false;
  return std::all_of(names.begin(), names.end(), [](const std::string& n) {
    return n == "cas" || n == "ac" || n == "locks" || n == "tmp";
  });
}

std::unique_ptr<FileLock> Cache::lock_for_build() {
  mark();
  return fs_.lock_shared(root_ / "locks" / "gc");
}
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
      auto text = fs_.read(p, nullptr, kMaxActionBytes);
      auto res = text ? ActionResult::from_json(*text, k) : std::nullopt;
      if (!res) {  // unreadable results are garbage
        if (fs_.remove(p)) ++r.actions_removed;
        continue;
      }
      actions.push_back({p, fs_.age_seconds(p).value_or(0), std::move(*res)});
    }
  // Most recently used first; keep results while their blobs fit in the budget.
  std::sort(actions.begin(), actions.end(),
            [](const Entry& a, const Entry& b) { return a.age != b.age ? a.age < b.age : a.path < b.path; });
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

VerifyResult Cache::verify_all() {
  VerifyResult r;
  for (const auto& fan : fs_.list(root_ / "cas"))
    for (const auto& b : fs_.list(root_ / "cas" / fan)) {
      const fs::path p = root_ / "cas" / fan / b;
      auto d = fs_.digest(p);
      if (!d || d->hash != b || fan != b.substr(0, 2)) {
        if (fs_.remove(p)) ++r.blobs_removed;
      }
    }
  // Action results are checked after the blobs: one naming a blob just deleted goes too.
  for (const auto& fan : fs_.list(root_ / "ac"))
    for (const auto& k : fs_.list(root_ / "ac" / fan)) {
      const fs::path p = root_ / "ac" / fan / k;
      auto text = fs_.read(p, nullptr, kMaxActionBytes);
      auto res = text && is_hex_digest(k) && fan == k.substr(0, 2) ? ActionResult::from_json(*text, k)
                                                                   : std::nullopt;
      bool ok = res.has_value();
      if (ok)
        for (const auto& o : res->outputs) {
          auto st = fs_.stat(blob_path(o.digest.hash));
          if (!st || st->is_dir || st->size != o.digest.size) ok = false;
        }
      if (!ok && fs_.remove(p)) ++r.actions_removed;
    }
  return r;
}

}  // namespace sylva
