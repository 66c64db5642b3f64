// The record format is a flat binary file (magic, then LEB128 integers, length-prefixed strings
// and raw 32-byte hashes) because a 10,000-node no-op reads it on every build: parsing it must
// cost less than the stat calls it saves, and a cold build writes it once per out dir (its size
// is most of sylva's bookkeeping bytes per node). Paths are kept as given (the recipe loader
// resolves them), so one file reached by two spellings is simply recorded twice.
#include "pipeline/digest_cache.h"

#include <algorithm>
#include <cstring>
#include <set>
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
  std::string_view view() {
    const std::uint64_t n = uint();
    if (!ok || s.size() - at < n) {
      ok = false;
      return {};
    }
    std::string_view v = s.substr(at, n);
    at += n;
    return v;
  }
  std::string str() { return std::string(view()); }
  // The 32 raw bytes of a hash, or nullptr if absent (or damaged: then ok is false).
  const char* raw_hash() {
    if (at >= s.size()) return ok = false, nullptr;
    if (s[at++] == '\0') return nullptr;
    if (s.size() - at < 32) return ok = false, nullptr;
    const char* h = s.data() + at;
    at += 32;
    return h;
  }
  std::string hash() {
    const char* h = raw_hash();
    return h ? hex_of(h) : std::string();
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
  static std::string hex_of(const char* raw) {
    std::string hex(64, '0');
    for (std::size_t i = 0; i < 32; ++i) {
      const auto b = static_cast<unsigned char>(raw[i]);
      hex[2 * i] = kHex[b >> 4];
      hex[2 * i + 1] = kHex[b & 15];
    }
    return hex;
  }
};

// True if the 32 raw bytes `raw` are the 64-digit lowercase hex `hex`.
bool raw_equals_hex(const char* raw, const std::string& hex) {
  if (hex.size() != 64) return false;
  for (std::size_t i = 0; i < 32; ++i) {
    const auto b = static_cast<unsigned char>(raw[i]);
    if (hex[2 * i] != kHex[b >> 4] || hex[2 * i + 1] != kHex[b & 15]) return false;
  }
  return true;
}

// One node record after its name: key, cache root, directory stat, explain-record key, outputs.
// `out` may be null (validation only: nothing is allocated). False if damaged.
bool read_node(Reader& r, PublishedNode* out) {
  const char* key = r.raw_hash();
  const std::string_view root = r.view();
  const FileInfo dir = r.stat();
  const char* record_key = r.raw_hash();
  const std::uint64_t outputs = r.uint();
  if (out) {
    out->tag = (key ? Reader::hex_of(key) : std::string()) + " " + std::string(root);
    out->dir = dir;
    out->record_key = record_key ? Reader::hex_of(record_key) : std::string();
    out->outputs.clear();
    out->outputs.reserve(std::min<std::uint64_t>(outputs, 1024));
  }
  for (std::uint64_t k = 0; k < outputs && r.ok; ++k) {
    const std::string_view name = r.view();
    const char* hash = r.raw_hash();
    const std::uint64_t size = r.uint();
    if (!hash) r.ok = false;
    if (out && r.ok) out->outputs.push_back({std::string(name), Digest{Reader::hex_of(hash), size}});
  }
  return r.ok && key != nullptr;
}

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
  text_.clear();
  base_.clear();
  base_nodes_.clear();
  entries_.clear();
  nodes_.clear();
  dirty_ = false;
  if (!text || text->size() < sizeof kMagic || std::memcmp(text->data(), kMagic, sizeof kMagic) != 0) return;
  text_ = std::move(*text);
  // Every record is checked here (without allocating); a damaged or unsorted file is an empty
  // cache, as if it were missing.
  Reader r{text_, sizeof kMagic};
  const std::uint64_t n = r.uint();
  base_.reserve(std::min<std::uint64_t>(n, text_.size()));
  for (std::uint64_t i = 0; i < n && r.ok; ++i) {
    const std::size_t begin = r.at;
    BaseEntry e{};
    e.path = r.view();
    e.stat = r.stat();
    e.hash = r.raw_hash();
    e.size = r.uint();
    e.begin = begin;
    e.end = r.at;
    if (!r.ok || !e.hash) continue;
    if (!base_.empty() && !(base_.back().path < e.path)) r.ok = false;
    base_.push_back(e);
  }
  const std::uint64_t m = r.uint();
  base_nodes_.reserve(std::min<std::uint64_t>(m, text_.size()));
  for (std::uint64_t i = 0; i < m && r.ok; ++i) {
    const std::size_t begin = r.at;
    const std::string_view name = r.view();
    const bool good = read_node(r, nullptr);
    if (!r.ok || !good) continue;
    if (!base_nodes_.empty() && !(base_nodes_.back().name < name)) r.ok = false;
    base_nodes_.push_back({name, begin, r.at});
  }
  if (!r.ok) {  // damaged: start afresh
    text_.clear();
    base_.clear();
    base_nodes_.clear();
  }
}

const DigestCache::BaseEntry* DigestCache::find_base(std::string_view path) const {
  auto it = std::lower_bound(base_.begin(), base_.end(), path,
                             [](const BaseEntry& e, std::string_view p) { return e.path < p; });
  return it == base_.end() || it->path != path ? nullptr : &*it;
}

std::optional<DigestCache::Entry> DigestCache::find_entry(const std::string& path) const {
  if (auto it = entries_.find(path); it != entries_.end()) return it->second;
  const BaseEntry* e = find_base(path);
  if (!e) return std::nullopt;
  return Entry{e->stat, Digest{Reader::hex_of(e->hash), e->size}};
}

bool DigestCache::find_node(const std::string& node, PublishedNode* out) const {
  if (auto it = nodes_.find(node); it != nodes_.end()) {
    if (it->second && out) *out = *it->second;
    return it->second.has_value();
  }
  auto it = std::lower_bound(base_nodes_.begin(), base_nodes_.end(), std::string_view(node),
                             [](const BaseNode& e, std::string_view p) { return e.name < p; });
  if (it == base_nodes_.end() || it->name != node) return false;
  if (!out) return true;
  Reader r{text_, it->begin};
  r.view();
  return read_node(r, out);
}

bool DigestCache::save(std::string* error) {
  std::string out;
  {
    std::lock_guard lock(mu_);
    if (!dirty_) return true;
    // Sorted, so the same records always give the same bytes. A loaded record nobody changed
    // is copied as it was; the others are encoded again.
    std::vector<std::pair<std::string_view, std::string>> records;
    records.reserve(base_.size() + entries_.size());
    for (const auto& e : base_)
      if (!entries_.count(std::string(e.path)))
        records.emplace_back(e.path, std::string(text_, e.begin, e.end - e.begin));
    for (const auto& [path, e] : entries_) {
      if (!e) continue;
      std::string rec;
      put_str(rec, path);
      put_stat(rec, e->stat);
      put_hash(rec, e->digest.hash);
      put_uint(rec, e->digest.size);
      records.emplace_back(path, std::move(rec));
    }
    std::sort(records.begin(), records.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    out.assign(kMagic, sizeof kMagic);
    put_uint(out, records.size());
    for (const auto& rec : records) out += rec.second;

    records.clear();
    for (const auto& e : base_nodes_)
      if (!nodes_.count(std::string(e.name)))
        records.emplace_back(e.name, std::string(text_, e.begin, e.end - e.begin));
    for (const auto& [name, node] : nodes_) {
      if (!node) continue;
      const PublishedNode& p = *node;
      std::string rec;
      put_str(rec, name);
      const std::size_t space = p.tag.find(' ');
      put_hash(rec, p.tag.substr(0, space));
      put_str(rec,
              space == std::string::npos ? std::string_view() : std::string_view(p.tag).substr(space + 1));
      put_stat(rec, p.dir);
      put_hash(rec, p.record_key);
      put_uint(rec, p.outputs.size());
      for (const auto& o : p.outputs) {
        put_str(rec, o.name);
        put_hash(rec, o.digest.hash);
        put_uint(rec, o.digest.size);
      }
      records.emplace_back(name, std::move(rec));
    }
    std::sort(records.begin(), records.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    put_uint(out, records.size());
    for (const auto& rec : records) out += rec.second;
    dirty_ = false;
  }
  if (fs_.write_atomic(file_, out, /*durable=*/false, error))
    return true;  // a cache: losing it costs hashing
  std::lock_guard lock(mu_);
  dirty_ = true;
  return false;
}

bool DigestCache::holds(const fs::path& p, const Digest& d) {
  const std::string& key = p.native();
  FileInfo recorded;
  {
    std::lock_guard lock(mu_);
    if (auto it = entries_.find(key); it != entries_.end()) {
      if (!it->second || !(it->second->digest == d)) return false;
      recorded = it->second->stat;
    } else {
      const BaseEntry* e = find_base(key);
      if (!e || e->size != d.size || !raw_equals_hex(e->hash, d.hash)) return false;
      recorded = e->stat;
    }
  }
  auto st = fs_.stat(p);
  return st && same_file(*st, recorded);
}

void DigestCache::record(const fs::path& p, const Digest& d, std::int64_t known_at) {
  auto st = fs_.stat(p);
  std::lock_guard lock(mu_);
  const std::string& key = p.native();
  const std::optional<Entry> now = find_entry(key);
  if (!st || !settled(st->mtime_ns, known_at) || st->is_dir || st->is_other) {
    if (now) {
      entries_[key] = std::nullopt;
      dirty_ = true;
    }
    return;
  }
  if (!now || !same_file(now->stat, *st) || !(now->digest == d)) {
    entries_[key] = Entry{*st, d};
    dirty_ = true;
  }
  linked_[{st->dev, st->ino}] = {key, d};
}

void DigestCache::settle_links() {
  std::lock_guard lock(mu_);
  if (linked_.empty()) return;  // a no-op linked nothing
  // The inodes' stats now, after the build's last link (one stat per inode).
  std::map<std::pair<std::uint64_t, std::uint64_t>, FileInfo> now;
  for (const auto& [inode, seen] : linked_) {
    auto cur = fs_.stat(seen.first);
    if (cur && !cur->is_dir && !cur->is_other && cur->dev == inode.first && cur->ino == inode.second)
      now.emplace(inode, *cur);
  }
  // Another link of one of those inodes: equal in everything but ctime (which links, chmod and
  // writes change, and a write also changes mtime or size), with the digest this build saw.
  auto current = [&](const FileInfo& st) -> const FileInfo* {
    auto it = now.find({st.dev, st.ino});
    if (it == now.end() || st.is_dir || st.is_other || st.size != it->second.size ||
        st.mtime_ns != it->second.mtime_ns || st.ctime_ns == it->second.ctime_ns)
      return nullptr;
    return &it->second;
  };
  std::vector<std::pair<std::string, const FileInfo*>> update;
  for (const BaseEntry& e : base_)
    if (const FileInfo* cur = current(e.stat)) {
      const Digest& d = linked_.at({e.stat.dev, e.stat.ino}).second;
      if (e.size == d.size && raw_equals_hex(e.hash, d.hash) && !entries_.count(std::string(e.path)))
        update.emplace_back(std::string(e.path), cur);
    }
  for (const auto& [key, entry] : entries_)
    if (entry)
      if (const FileInfo* cur = current(entry->stat);
          cur && entry->digest == linked_.at({cur->dev, cur->ino}).second)
        update.emplace_back(key, cur);
  for (const auto& [key, cur] : update) {
    entries_[key] = Entry{*cur, linked_.at({cur->dev, cur->ino}).second};
    dirty_ = true;
  }
  linked_.clear();
}

void DigestCache::forget(const fs::path& p) {
  std::lock_guard lock(mu_);
  if (find_entry(p.native())) {
    entries_[p.native()] = std::nullopt;
    dirty_ = true;
  }
}

std::optional<PublishedNode> DigestCache::published(const std::string& node) {
  std::lock_guard lock(mu_);
  PublishedNode p;
  if (!find_node(node, &p)) return std::nullopt;
  return p;
}

void DigestCache::set_published(const std::string& node, PublishedNode p) {
  std::lock_guard lock(mu_);
  PublishedNode now;
  if (find_node(node, &now) && now == p) return;
  nodes_[node] = std::move(p);
  dirty_ = true;
}

void DigestCache::forget_published(const std::string& node) {
  std::lock_guard lock(mu_);
  if (find_node(node, nullptr)) {
    nodes_[node] = std::nullopt;
    dirty_ = true;
  }
}

std::vector<std::string> DigestCache::published_nodes() {
  std::lock_guard lock(mu_);
  std::set<std::string> names;
  for (const BaseNode& b : base_nodes_) {
    std::string name(b.name);
    if (!nodes_.contains(name)) names.insert(std::move(name));
  }
  for (const auto& [name, p] : nodes_)
    if (p) names.insert(name);
  return {names.begin(), names.end()};
}

std::optional<Digest> DigestCache::digest(const fs::path& p, std::string* error,
                                          const std::optional<FileInfo>& known) {
  auto st = known ? known : fs_.stat(p);
  if (!st) {
    if (error) *error = "No such file or directory";
    return std::nullopt;
  }
  {
    std::lock_guard lock(mu_);
    auto e = find_entry(p.native());
    if (e && same_file(e->stat, *st)) return std::move(e->digest);
  }
  const std::int64_t known_at = fs_.now_ns();
  auto d = fs_.digest(p, error);
  if (d) record(p, *d, known_at);
  return d;
}

std::optional<Digest> DigestCache::digest_dir(const fs::path& p, std::string* error, std::size_t max_files) {
  // 1. The listing, depth-first over FileSystem::list (so the fake file system works the same),
  // counted before anything is hashed: a folder over the limit costs stats, not reads.
  struct Found {
    fs::path full;
    std::string rel;
    FileInfo st;
  };
  std::vector<Found> found;
  std::vector<std::pair<fs::path, std::string>> todo{{p, ""}};
  while (!todo.empty()) {
    auto [dir, rel] = todo.back();
    todo.pop_back();
    for (const auto& name : fs_.list(dir)) {
      const fs::path full = dir / name;
      std::string r = rel.empty() ? name : rel + "/" + name;
      auto st = fs_.stat(full);
      if (!st || st->is_other) continue;  // FIFOs, devices and sockets are not content
      if (st->is_dir) {
        todo.emplace_back(full, std::move(r));
        continue;
      }
      if (found.size() == max_files) {
        if (error) *error = "holds more than " + std::to_string(max_files) + " files";
        return std::nullopt;
      }
      found.push_back({full, std::move(r), *st});
    }
  }
  // 2. Each file's digest (recorded ones unread when their stat is unchanged).
  std::vector<std::pair<std::string, Digest>> entries;
  entries.reserve(found.size());
  for (auto& f : found) {
    auto d = digest(f.full, error, f.st);
    if (!d) return std::nullopt;
    entries.emplace_back(std::move(f.rel), std::move(*d));
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
