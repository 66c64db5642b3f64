// An in-memory FileSystem for tests: records every write and every content read, keeps a stat
// (inode, mtime, ctime) per file stamped from a clock the test controls, can be told to fail
// writes whose path contains a given substring (to prove that failures leave nothing
// half-written), and models durability: a file survives a power loss (durable()) once, after its
// last write, rename or link into place, both the file and its directory were synced.
#pragma once

#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "pipeline/filesystem.h"

namespace sylva::test {

class FakeFileSystem final : public FileSystem {
 public:
  std::map<std::string, std::string> files;  // path -> content
  std::map<std::string, double> ages;        // path -> seconds since modified (default 0)
  std::vector<std::string> writes;           // every successful write_atomic/copy/link/rename target
  std::vector<std::string> reads;            // every read() and digest() of a file's content
  std::string fail_writes_containing;        // non-empty: such writes fail ...
  std::string fail_reason = "No space left on device";  // ... with this reason
  int syncs = 0;                                        // sync() calls
  // "write <path>", "rename <to>", "link <to>", "sync <path>" and "syncfs", in order.
  std::vector<std::string> events;
  // Called after every successful write_atomic() or create()d file's close(), with the path.
  std::function<void(const std::string&)> on_write;
  std::int64_t now = 1'700'000'000'123'456'789;  // the file-system clock (ns); tests advance it
  std::uint64_t free = 1ull << 40;               // free_bytes()

  // Content written behind the fake's back keeps a stat from the current clock.
  void put(const std::string& path, const std::string& content) {
    std::lock_guard<std::recursive_mutex> l(mu_);
    files[key(path)] = content;
    stamp(key(path), true);
  }

  std::optional<std::string> read(const fs::path& p, std::string* error = nullptr,
                                  std::uint64_t max_bytes = UINT64_MAX) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    auto it = files.find(key(p));
    if (it == files.end()) {
      if (error) *error = "No such file or directory";
      return std::nullopt;
    }
    if (it->second.size() > max_bytes) {
      if (error) *error = "larger than " + std::to_string(max_bytes) + " bytes";
      return std::nullopt;
    }
    reads.push_back(it->first);
    return it->second;
  }
  bool write_atomic(const fs::path& p, std::string_view bytes, bool durable = true,
                    std::string* error = nullptr) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(p);
    if (failing(k)) return fail(error);
    files[k] = std::string(bytes);
    ages[k] = 0;
    stamp(k, true);
    writes.push_back(k);
    changed(k, "write ");
    if (durable) {
      sync(k);
      sync(fs::path(k).parent_path());
    }
    if (on_write) on_write(k);
    return true;
  }
  std::unique_ptr<WritableFile> create(const fs::path& p, std::string* error = nullptr) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(p);
    if (failing(k)) {
      fail(error);
      return nullptr;
    }
    return std::make_unique<File>(*this, k);
  }
  // True if `path` would survive a power loss now (see the header).
  bool durable(const std::string& path) {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(path);
    auto changed_at = last_change_.find(k);
    if (!files.count(k) || changed_at == last_change_.end()) return false;
    auto synced = last_sync_.find(k);
    auto dir_synced = last_sync_.find(fs::path(k).parent_path().string());
    return synced != last_sync_.end() && synced->second > changed_at->second &&
           dir_synced != last_sync_.end() && dir_synced->second > changed_at->second;
  }
  bool copy_atomic(const fs::path& from, const fs::path& to, std::string* error = nullptr) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    auto it = files.find(key(from));
    return it != files.end() && write_atomic(to, std::string(it->second), true, error);
  }
  std::optional<FileInfo> stat(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(p);
    if (auto it = files.find(k); it != files.end()) {
      FileInfo info = meta_[k];
      info.is_dir = false;
      info.size = it->second.size();
      return info;
    }
    const std::string prefix = k == "/" ? k : k + "/";
    for (const auto& [f, c] : files)
      if (f.size() > prefix.size() && f.compare(0, prefix.size(), prefix) == 0) {
        FileInfo info = dir_meta_[k];
        info.is_dir = true;
        return info;
      }
    return std::nullopt;
  }
  bool remove(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(p);
    if (files.erase(k)) touch_parent(k);
    return true;
  }
  bool remove_all(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(p);
    for (auto it = files.begin(); it != files.end();)
      if (it->first == k || it->first.rfind(k + "/", 0) == 0) {
        touch_parent(it->first);
        it = files.erase(it);
      } else {
        ++it;
      }
    return true;
  }
  bool make_dirs(const fs::path&, std::string* = nullptr) override { return true; }
  std::vector<std::string> list(const fs::path& dir) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(dir) + "/";
    std::set<std::string> names;
    for (const auto& [f, c] : files)
      if (f.rfind(k, 0) == 0) names.insert(f.substr(k.size(), f.find('/', k.size()) - k.size()));
    return {names.begin(), names.end()};
  }
  std::unique_ptr<FileLock> lock(const fs::path&) override { return std::make_unique<FileLock>(); }
  std::unique_ptr<FileLock> lock_shared(const fs::path&) override { return std::make_unique<FileLock>(); }
  std::unique_ptr<FileLock> try_lock(const fs::path&) override { return std::make_unique<FileLock>(); }
  void make_read_only(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    meta_[key(p)].ctime_ns = now;
  }
  void touch(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    ages[key(p)] = 0;
    meta_[key(p)].mtime_ns = meta_[key(p)].ctime_ns = now;
  }
  std::optional<double> age_seconds(const fs::path& p) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(p);
    if (auto it = ages.find(k); it != ages.end()) return it->second;
    return stat(p) ? std::optional<double>(0.0) : std::nullopt;
  }
  std::optional<Digest> digest(const fs::path& p, std::string* error = nullptr) override {
    auto bytes = read(p, error);
    if (!bytes) return std::nullopt;
    return digest_bytes(*bytes);
  }
  bool link_or_copy(const fs::path& from, const fs::path& to, bool* linked = nullptr,
                    std::string* error = nullptr) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string f = key(from), t = key(to);
    auto it = files.find(f);
    if (it == files.end()) {
      if (error) *error = "No such file or directory";
      return false;
    }
    if (failing(t)) return fail(error);
    files[t] = it->second;
    meta_[f].ctime_ns = now;  // a new link changes the inode's ctime
    meta_[t] = meta_[f];
    touch_parent(t);
    writes.push_back(t);
    changed(t, "link ");
    if (linked) *linked = true;
    return true;
  }
  bool sync(const fs::path& p, std::string* error = nullptr) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(p);
    if (failing("<sync>")) return fail(error);
    if (!stat(p)) {
      if (error) *error = "No such file or directory";
      return false;
    }
    ++syncs;
    last_sync_[k] = ++clock_;
    events.push_back("sync " + k);
    return true;
  }
  // Renames a file, or a directory (every file below it).
  bool rename(const fs::path& from, const fs::path& to, std::string* error = nullptr) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string f = key(from), t = key(to);
    auto it = files.find(f);
    if (failing(t)) return fail(error);
    if (it == files.end()) {
      const std::string prefix = f + "/";
      std::vector<std::string> moved;
      for (const auto& [k, v] : files)
        if (k.rfind(prefix, 0) == 0) moved.push_back(k);
      if (moved.empty()) {
        if (error) *error = "No such file or directory";
        return false;
      }
      remove_all(to);
      for (const auto& k : moved) {
        const std::string nk = t + k.substr(f.size());
        files[nk] = std::move(files[k]);
        files.erase(k);
        meta_[nk] = meta_[k];
      }
      dir_meta_[t] = dir_meta_[f];
      dir_meta_[t].ctime_ns = now;
      dir_meta_.erase(f);
      touch_parent(f);
      touch_parent(t);
      writes.push_back(t);
      changed(t, "rename ");
      return true;
    }
    files[t] = std::move(it->second);
    files.erase(it);
    meta_[t] = meta_[f];
    meta_[t].ctime_ns = now;
    touch_parent(f);
    touch_parent(t);
    writes.push_back(t);
    changed(t, "rename ");
    return true;
  }
  void set_mtime(const fs::path& p, std::int64_t mtime_ns) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    const std::string k = key(p);
    FileInfo& m = files.count(k) ? meta_[k] : dir_meta_[k];
    m.mtime_ns = mtime_ns;
    m.ctime_ns = now;
  }
  std::int64_t now_ns() override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    return now;
  }
  std::optional<std::uint64_t> free_bytes(const fs::path&) override { return free; }
  bool replace_dir(const fs::path& staged, const fs::path& dest, fs::path* displaced,
                   std::string* error = nullptr) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    if (displaced) displaced->clear();
    if (stat(dest)) {
      const fs::path old = staged.string() + ".old";
      if (!rename(dest, old, error)) return false;
      if (displaced) *displaced = old;
    }
    if (!stat(staged)) {  // an empty staged directory holds no files in this fake: nothing to move
      dir_meta_[key(dest)] = dir_meta_[key(staged)];
      return true;
    }
    return rename(staged, dest, error);
  }
  // Every file and directory becomes durable.
  bool sync_fs(const fs::path&, std::string* error = nullptr) override {
    std::lock_guard<std::recursive_mutex> l(mu_);
    if (failing("<sync>")) return fail(error);
    ++syncs;
    const std::uint64_t at = ++clock_;
    for (const auto& [f, c] : files) {
      last_sync_[f] = at;
      for (fs::path d = fs::path(f).parent_path(); !d.empty() && d != d.parent_path(); d = d.parent_path())
        last_sync_[d.string()] = at;
    }
    events.push_back("syncfs");
    return true;
  }
  std::optional<fs::path> real_path(const fs::path& p) override {
    if (!stat(p)) return std::nullopt;
    return fs::path(key(p));
  }

 private:
  // A file being written with create(): its bytes appear on close().
  class File final : public WritableFile {
   public:
    File(FakeFileSystem& fs, std::string path) : fs_(fs), path_(std::move(path)) {}
    ~File() override { close(); }
    bool append(const char* data, std::size_t n, std::string* error = nullptr) override {
      if (fs_.failing(path_)) return fs_.fail(error);
      bytes_.append(data, n);
      return true;
    }
    bool close(std::string* = nullptr) override {
      if (closed_) return true;
      closed_ = true;
      return fs_.write_atomic(path_, bytes_, /*durable=*/false);
    }

   private:
    FakeFileSystem& fs_;
    std::string path_, bytes_;
    bool closed_ = false;
  };

  static std::string key(const fs::path& p) { return p.lexically_normal().string(); }
  // Every change to what `k` names (a write, a rename or link into place), for durable().
  void changed(const std::string& k, const char* what) {
    last_change_[k] = ++clock_;
    events.push_back(what + k);
    // A directory renamed into place: the files below it moved too.
    for (const auto& [f, c] : files)
      if (f.size() > k.size() && f.compare(0, k.size(), k) == 0 && f[k.size()] == '/')
        last_change_[f] = clock_;
  }
  bool fail(std::string* error) const {
    if (error) *error = fail_reason;
    return false;
  }
  bool failing(const std::string& k) const {
    return !fail_writes_containing.empty() && k.find(fail_writes_containing) != std::string::npos;
  }
  // A write makes a new inode (temp + rename) stamped now, and changes its directory.
  void stamp(const std::string& k, bool new_inode) {
    FileInfo& m = meta_[k];
    if (new_inode) m.ino = ++next_ino_;
    m.mtime_ns = m.ctime_ns = now;
    touch_parent(k);
  }
  void touch_parent(const std::string& k) {
    const std::string dir = fs::path(k).parent_path().string();
    FileInfo& d = dir_meta_[dir];
    if (d.ino == 0) d.ino = ++next_ino_;
    d.mtime_ns = d.ctime_ns = now;
  }

  std::recursive_mutex mu_;
  std::map<std::string, FileInfo> meta_, dir_meta_;
  std::uint64_t next_ino_ = 0;
  std::map<std::string, std::uint64_t> last_change_, last_sync_;  // event clock per path
  std::uint64_t clock_ = 0;
};

}  // namespace sylva::test
