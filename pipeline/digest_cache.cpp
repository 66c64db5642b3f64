// The record format is a flat binary file (magic, then length-prefixed fields) because a
// 10,000-node no-op reads it on every build: parsing it must cost less than the stat calls it
// saves. Paths are kept as given (the recipe loader resolves them), so one file reached by two
// spellings is simply recorded twice.
#include "pipeline/digest_cache.h"

#include <algorithm>
#include <cstring>
#include <vector>

namespace sylva {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'S', 'Y', 'D', 'C', 'A', 'C', 'H', '1'};

void put_u64(std::string& out, std::uint64_t v) {
  char b[8];
  std::memcpy(b, &v, 8);
  out.append(b, 8);
}
void put_str(std::string& out, const std::string& s) {
  put_u64(out, s.size());
  out += s;
}

struct Reader {
  const std::string& s;
  std::size_t at = 0;
  bool ok = true;
  std::uint64_t u64() {
    if (s.size() - at < 8) {
      ok = false;
      return 0;
    }
    std::uint64_t v;
    std::memcpy(&v, s.data() + at, 8);
    at += 8;
    return v;
  }
  std::string str() {
    const std::uint64_t n = u64();
    if (!ok || s.size() - at < n) {
      ok = false;
      return {};
    }
    std::string v = s.substr(at, n);
    at += n;
    return v;
  }
};

bool same_file(const FileInfo& a, const FileInfo& b) {
  return a.is_dir == b.is_dir && a.size == b.size && a.mtime_ns == b.mtime_ns && a.ctime_ns == b.ctime_ns &&
         a.ino == b.ino && a.dev == b.dev;
}

}  // namespace

DigestCache::DigestCache(FileSystem& fs, fs::path file) : fs_(fs), file_(std::move(file)) {}

bool DigestCache::settled(std::int64_t mtime_ns, std::int64_t known_at) {
  constexpr std::int64_t kSecond = 1000000000;
  if (mtime_ns % kSecond == 0) return mtime_ns + 2 * kSecond <= known_at;
  return mtime_ns < known_at;
}

void DigestCache::load() {
  auto text = fs_.read(file_);
  std::lock_guard lock(mu_);
  entries_.clear();
  notes_.clear();
  if (!text || text->size() < sizeof kMagic || std::memcmp(text->data(), kMagic, sizeof kMagic) != 0) return;
  Reader r{*text, sizeof kMagic};
  const std::uint64_t n = r.u64();
  for (std::uint64_t i = 0; i < n && r.ok; ++i) {
    std::string path = r.str();
    Entry e;
    e.stat.is_dir = r.u64() != 0;
    e.stat.size = r.u64();
    e.stat.mtime_ns = static_cast<std::int64_t>(r.u64());
    e.stat.ctime_ns = static_cast<std::int64_t>(r.u64());
    e.stat.ino = r.u64();
    e.stat.dev = r.u64();
    e.digest.hash = r.str();
    e.digest.size = r.u64();
    if (r.ok && is_hex_digest(e.digest.hash)) entries_.emplace(std::move(path), std::move(e));
  }
  const std::uint64_t m = r.u64();
  for (std::uint64_t i = 0; i < m && r.ok; ++i) {
    std::string k = r.str();
    std::string v = r.str();
    if (r.ok) notes_.emplace(std::move(k), std::move(v));
  }
  if (!r.ok) {  // damaged: start afresh
    entries_.clear();
    notes_.clear();
  }
}

bool DigestCache::save() {
  std::string out;
  {
    std::lock_guard lock(mu_);
    if (!dirty_) return true;
    // Sorted, so the same records always give the same bytes.
    std::vector<const std::pair<const std::string, Entry>*> sorted;
    for (const auto& kv : entries_) sorted.push_back(&kv);
    std::sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->first < b->first; });
    out.assign(kMagic, sizeof kMagic);
    put_u64(out, sorted.size());
    for (const auto* kv : sorted) {
      const Entry& e = kv->second;
      put_str(out, kv->first);
      put_u64(out, e.stat.is_dir ? 1 : 0);
      put_u64(out, e.stat.size);
      put_u64(out, static_cast<std::uint64_t>(e.stat.mtime_ns));
      put_u64(out, static_cast<std::uint64_t>(e.stat.ctime_ns));
      put_u64(out, e.stat.ino);
      put_u64(out, e.stat.dev);
      put_str(out, e.digest.hash);
      put_u64(out, e.digest.size);
    }
    std::vector<std::pair<std::string, std::string>> notes(notes_.begin(), notes_.end());
    std::sort(notes.begin(), notes.end());
    put_u64(out, notes.size());
    for (const auto& [k, v] : notes) {
      put_str(out, k);
      put_str(out, v);
    }
    dirty_ = false;
  }
  return fs_.write_atomic(file_, out, /*durable=*/false);  // a cache: losing it costs hashing
}

bool DigestCache::holds(const fs::path& p, const Digest& d) {
  const std::string key = p.string();
  {
    std::lock_guard lock(mu_);
    auto it = entries_.find(key);
    if (it == entries_.end() || !(it->second.digest == d)) return false;
  }
  auto st = fs_.stat(p);
  std::lock_guard lock(mu_);
  auto it = entries_.find(key);
  return st && it != entries_.end() && it->second.digest == d && same_file(*st, it->second.stat);
}

void DigestCache::record(const fs::path& p, const Digest& d, std::int64_t known_at) {
  auto st = fs_.stat(p);
  std::lock_guard lock(mu_);
  const std::string key = p.string();
  if (!st || !settled(st->mtime_ns, known_at)) {
    if (entries_.erase(key)) dirty_ = true;
    return;
  }
  auto [it, inserted] = entries_.try_emplace(key);
  if (inserted || !same_file(it->second.stat, *st) || !(it->second.digest == d)) {
    it->second = Entry{*st, d};
    dirty_ = true;
  }
}

void DigestCache::forget(const fs::path& p) {
  std::lock_guard lock(mu_);
  if (entries_.erase(p.string())) dirty_ = true;
}

std::optional<Digest> DigestCache::digest(const fs::path& p, std::string* error) {
  auto st = fs_.stat(p);
  if (!st) {
    if (error) *error = "No such file or directory";
    return std::nullopt;
  }
  {
    std::lock_guard lock(mu_);
    auto it = entries_.find(p.string());
    if (it != entries_.end() && same_file(it->second.stat, *st)) return it->second.digest;
  }
  const std::int64_t known_at = fs_.now_ns();
  auto d = fs_.digest(p, error);
  if (d) record(p, *d, known_at);
  return d;
}

std::optional<Digest> DigestCache::digest_dir(const fs::path& p, std::string* error) {
  std::vector<std::pair<std::string, Digest>> entries;
  // Depth-first over FileSystem::list, so the fake file system works the same.
  std::vector<std::pair<fs::path, std::string>> todo{{p, ""}};
  while (!todo.empty()) {
    auto [dir, rel] = todo.back();
    todo.pop_back();
    for (const auto& name : fs_.list(dir)) {
      const fs::path full = dir / name;
      const std::string r = rel.empty() ? name : rel + "/" + name;
      auto st = fs_.stat(full);
      if (!st) continue;
      if (st->is_dir) {
        todo.emplace_back(full, r);
        continue;
      }
      auto d = digest(full, error);
      if (!d) return std::nullopt;
      entries.emplace_back(r, *d);
    }
  }
  if (!fs_.stat(p)) {
    if (error) *error = "No such file or directory";
    return std::nullopt;
  }
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::string listing;
  for (const auto& [rel, d] : entries) listing += rel + '\0' + d.hash + '\n';
  return digest_bytes(listing);
}

std::optional<std::string> DigestCache::note(const std::string& name) {
  std::lock_guard lock(mu_);
  auto it = notes_.find(name);
  if (it == notes_.end()) return std::nullopt;
  return it->second;
}

void DigestCache::set_note(const std::string& name, const std::string& value) {
  std::lock_guard lock(mu_);
  auto [it, inserted] = notes_.try_emplace(name, value);
  if (!inserted && it->second == value) return;
  it->second = value;
  dirty_ = true;
}

}  // namespace sylva
