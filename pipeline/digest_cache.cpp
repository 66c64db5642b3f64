// The record format is a flat binary file (magic, then LEB128 integers, length-prefixed strings
// and raw 32-byte hashes) because a 10,000-node no-op reads it on every build: parsing it must
// cost less than the stat calls it saves, and a cold build writes it once per out dir (its size
// is most of sylva's bookkeeping bytes per node). Paths are kept as given (the recipe loader
// resolves them), so one file reached by two spellings is simply recorded twice.
#include "pipeline/digest_cache.h"

#include <algorithm>
#include <cstring>
#include <vector>

namespace sylva {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'S', 'Y', 'D', 'C', 'A', 'C', 'H', '2'};
constexpr char kHex[] = "0123456789abcdef";

void put_uint(std::string& out, std::uint64_t v) {
  while (v >= 0x80) {
    out += static_cast<char>((v & 0x7f) | 0x80);
    v >>= 7;
  }
  out += static_cast<char>(v);
}
void put_str(std::string& out, std::string_view s) {
  put_uint(out, s.size());
  out += s;
}
// A 64-digit hex hash as 32 bytes ("" as one zero byte of length: absent).
void put_hash(std::string& out, const std::string& hex) {
  if (hex.size() != 64) {
    out += '\0';
    return;
  }
  out += '\1';
  for (std::size_t i = 0; i < 64; i += 2) {
    auto nib = [](char c) { return c <= '9' ? c - '0' : c - 'a' + 10; };
    out += static_cast<char>((nib(hex[i]) << 4) | nib(hex[i + 1]));
  }
}
void put_stat(std::string& out, const FileInfo& st) {
  out += static_cast<char>((st.is_dir ? 1 : 0) | (st.is_other ? 2 : 0));
  put_uint(out, st.size);
  put_uint(out, static_cast<std::uint64_t>(st.mtime_ns));
  put_uint(out, static_cast<std::uint64_t>(st.ctime_ns));
  put_uint(out, st.ino);
  put_uint(out, st.dev);
}

struct Reader {
  std::string_view s;
  std::size_t at = 0;
  bool ok = true;
  std::uint64_t uint() {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (at >= s.size()) break;
      const auto b = static_cast<unsigned char>(s[at++]);
      v |= std::uint64_t(b & 0x7f) << shift;
      if (!(b & 0x80)) return v;
    }
    ok = false;
    return 0;
  }
  std::string str() {
    const std::uint64_t n = uint();
    if (!ok || s.size() - at < n) {
      ok = false;
      return {};
    }
    std::string v(s.substr(at, n));
    at += n;
    return v;
  }
  std::string hash() {
    if (at >= s.size()) return ok = false, std::string();
    if (s[at++] == '\0') return {};
    if (s.size() - at < 32) return ok = false, std::string();
    std::string hex(64, '0');
    for (std::size_t i = 0; i < 32; ++i) {
      const auto b = static_cast<unsigned char>(s[at + i]);
      hex[2 * i] = kHex[b >> 4];
      hex[2 * i + 1] = kHex[b & 15];
    }
    at += 32;
    return hex;
  }
  FileInfo stat() {
    FileInfo st;
    if (at >= s.size()) return ok = false, st;
    const auto flags = static_cast<unsigned char>(s[at++]);
    st.is_dir = flags & 1;
    st.is_other = flags & 2;
    st.size = uint();
    st.mtime_ns = static_cast<std::int64_t>(uint());
    st.ctime_ns = static_cast<std::int64_t>(uint());
    st.ino = uint();
    st.dev = uint();
    return st;
  }
};

}  // namespace

DigestCache::DigestCache(FileSystem& fs, fs::path file) : fs_(fs), file_(std::move(file)) {}

bool DigestCache::settled(std::int64_t mtime_ns, std::int64_t known_at) {
  constexpr std::int64_t kSecond = 1000000000;
  if (mtime_ns % kSecond == 0) return mtime_ns + 2 * kSecond <= known_at;
  return mtime_ns < known_at;
}

bool DigestCache::same_file(const FileInfo& a, const FileInfo& b) {
  return a.ino != 0 && a.is_dir == b.is_dir && a.is_other == b.is_other && a.size == b.size &&
         a.mtime_ns == b.mtime_ns && a.ctime_ns == b.ctime_ns && a.ino == b.ino && a.dev == b.dev;
}

void DigestCache::load() {
  auto text = fs_.read(file_);
  std::lock_guard lock(mu_);
  entries_.clear();
  nodes_.clear();
  if (!text || text->size() < sizeof kMagic || std::memcmp(text->data(), kMagic, sizeof kMagic) != 0) return;
  Reader r{*text, sizeof kMagic};
  const std::uint64_t n = r.uint();
  entries_.reserve(std::min<std::uint64_t>(n, text->size()));
  for (std::uint64_t i = 0; i < n && r.ok; ++i) {
    std::string path = r.str();
    Entry e;
    e.stat = r.stat();
    e.digest.hash = r.hash();
    e.digest.size = r.uint();
    if (r.ok && !e.digest.hash.empty()) entries_.emplace(std::move(path), std::move(e));
  }
  const std::uint64_t m = r.uint();
  nodes_.reserve(std::min<std::uint64_t>(m, text->size()));
  for (std::uint64_t i = 0; i < m && r.ok; ++i) {
    std::string name = r.str();
    PublishedNode p;
    const std::string key = r.hash();
    p.tag = key + " " + r.str();
    p.dir = r.stat();
    p.record_key = r.hash();
    const std::uint64_t outputs = r.uint();
    for (std::uint64_t k = 0; k < outputs && r.ok; ++k) {
      OutputEntry o;
      o.name = r.str();
      o.digest.hash = r.hash();
      o.digest.size = r.uint();
      if (o.digest.hash.empty()) r.ok = false;
      p.outputs.push_back(std::move(o));
    }
    if (r.ok && key.size() == 64) nodes_.emplace(std::move(name), std::move(p));
  }
  if (!r.ok) {  // damaged: start afresh
    entries_.clear();
    nodes_.clear();
  }
}

bool DigestCache::save(std::string* error) {
  std::string out;
  {
    std::lock_guard lock(mu_);
    if (!dirty_) return true;
    // Sorted, so the same records always give the same bytes.
    std::vector<const std::pair<const std::string, Entry>*> sorted;
    sorted.reserve(entries_.size());
    for (const auto& kv : entries_) sorted.push_back(&kv);
    std::sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->first < b->first; });
    out.assign(kMagic, sizeof kMagic);
    put_uint(out, sorted.size());
    for (const auto* kv : sorted) {
      put_str(out, kv->first);
      put_stat(out, kv->second.stat);
      put_hash(out, kv->second.digest.hash);
      put_uint(out, kv->second.digest.size);
    }
    std::vector<const std::pair<const std::string, PublishedNode>*> nodes;
    nodes.reserve(nodes_.size());
    for (const auto& kv : nodes_) nodes.push_back(&kv);
    std::sort(nodes.begin(), nodes.end(), [](auto* a, auto* b) { return a->first < b->first; });
    put_uint(out, nodes.size());
    for (const auto* kv : nodes) {
      const PublishedNode& p = kv->second;
      put_str(out, kv->first);
      const std::size_t space = p.tag.find(' ');
      put_hash(out, p.tag.substr(0, space));
      put_str(out, space == std::string::npos ? std::string_view() : std::string_view(p.tag).substr(space + 1));
      put_stat(out, p.dir);
      put_hash(out, p.record_key);
      put_uint(out, p.outputs.size());
      for (const auto& o : p.outputs) {
        put_str(out, o.name);
        put_hash(out, o.digest.hash);
        put_uint(out, o.digest.size);
      }
    }
    dirty_ = false;
  }
  if (fs_.write_atomic(file_, out, /*durable=*/false, error)) return true;  // a cache: losing it costs hashing
  std::lock_guard lock(mu_);
  dirty_ = true;
  return false;
}

bool DigestCache::holds(const fs::path& p, const Digest& d) {
  const std::string key = p.string();
  FileInfo recorded;
  {
    std::lock_guard lock(mu_);
    auto it = entries_.find(key);
    if (it == entries_.end() || !(it->second.digest == d)) return false;
    recorded = it->second.stat;
  }
  auto st = fs_.stat(p);
  return st && same_file(*st, recorded);
}

void DigestCache::record(const fs::path& p, const Digest& d, std::int64_t known_at) {
  auto st = fs_.stat(p);
  std::lock_guard lock(mu_);
  const std::string key = p.string();
  if (!st || !settled(st->mtime_ns, known_at) || st->is_dir || st->is_other) {
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

std::optional<PublishedNode> DigestCache::published(const std::string& node) {
  std::lock_guard lock(mu_);
  auto it = nodes_.find(node);
  if (it == nodes_.end()) return std::nullopt;
  return it->second;
}

void DigestCache::set_published(const std::string& node, PublishedNode p) {
  std::lock_guard lock(mu_);
  auto [it, inserted] = nodes_.try_emplace(node);
  if (!inserted && it->second == p) return;
  it->second = std::move(p);
  dirty_ = true;
}

void DigestCache::forget_published(const std::string& node) {
  std::lock_guard lock(mu_);
  if (nodes_.erase(node)) dirty_ = true;
}

std::optional<Digest> DigestCache::digest(const fs::path& p, std::string* error, const std::optional<FileInfo>& known) {
  auto st = known ? known : fs_.stat(p);
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
      if (!st || st->is_other) continue;  // FIFOs, devices and sockets are not content
      if (st->is_dir) {
        todo.emplace_back(full, r);
        continue;
      }
      auto d = digest(full, error, st);
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

}  // namespace sylva
