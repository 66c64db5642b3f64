#include "pipeline/out_dir.h"

#include <algorithm>

namespace sylva {

namespace fs = std::filesystem;

namespace {

bool same_names(const std::vector<OutputEntry>& a, const std::vector<OutputEntry>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](const OutputEntry& x, const OutputEntry& y) { return x.name == y.name; });
}

}  // namespace

OutDir::OutDir(FileSystem& fs, BlobStore& blobs, fs::path dir)
    : fs_(fs), blobs_(blobs), dir_(std::move(dir)), digests_(fs, dir_ / ".sylva" / "digests") {
  digests_.load();
}

fs::path OutDir::explain_record(const std::string& node) const { return dir_ / ".sylva" / (node + ".json"); }

bool OutDir::holds(const std::string& node, const PublishedNode& p) {
  const fs::path dir = node_dir(node);
  auto st = fs_.stat(dir);
  if (!st || !DigestCache::same_file(*st, p.dir)) return false;
  for (const auto& o : p.outputs)
    if (!digests_.holds(dir / o.name, o.digest)) return false;
  return true;
}

std::optional<FileInfo> OutDir::publish(const std::string& node, const std::vector<OutputEntry>& outputs,
                                        bool fresh, std::string* error) {
  const fs::path dest = node_dir(node);
  auto prev = digests_.published(node);
  if (prev && same_names(prev->outputs, outputs)) {
    PublishedNode now = *prev;
    now.outputs = outputs;
    if (holds(node, now)) return prev->dir;
  }
  const fs::path staged = unique_temp_path(dir_ / ("." + node));
  // Entries added to it before this clock reading are older than its mtime set below; any
  // later change makes the directory's stat differ (the racy rule, as for blobs).
  const std::int64_t dir_known_at = fs_.now_ns();
  auto abandon = [&](const std::string& why) -> std::optional<FileInfo> {
    fs_.remove_all(staged);
    if (error) *error = why;
    return std::nullopt;
  };
  std::string why;
  if (!fs_.make_dirs(staged, &why)) return abandon("cannot create " + staged.string() + ": " + why);
  std::vector<std::int64_t> known_at(outputs.size(), 0);
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const OutputEntry& o = outputs[k];
    const fs::path current = dest / o.name;
    if (digests_.holds(current, o.digest)) {  // the file there is right: link it, unread
      known_at[k] = fs_.now_ns();
      if (fs_.link_or_copy(current, staged / o.name, nullptr, &why)) continue;
    }
    if (!blobs_.materialize(o.digest, staged / o.name, !fresh, &known_at[k], &why))
      return abandon("cannot publish " + o.name + ": " + why);
  }
  fs_.set_mtime(staged, dir_known_at - 1);
  fs::path displaced;
  if (!fs_.replace_dir(staged, dest, &displaced, &why))
    return abandon("cannot publish into " + dest.string() + ": " + why);
  if (!displaced.empty()) fs_.remove_all(displaced);
  for (std::size_t k = 0; k < outputs.size(); ++k)
    digests_.record(dest / outputs[k].name, outputs[k].digest, known_at[k]);
  auto st = fs_.stat(dest);
  if (!st || !DigestCache::settled(st->mtime_ns, dir_known_at)) return FileInfo{};  // not trusted next time
  return st;
}

void OutDir::withdraw(const std::string& node) {
  digests_.forget_published(node);
  const fs::path dir = node_dir(node);
  if (!fs_.stat(dir)) return;
  const fs::path aside = unique_temp_path(dir_ / ("." + node));
  if (fs_.rename(dir, aside))
    fs_.remove_all(aside);
  else
    fs_.remove_all(dir);
}

}  // namespace sylva
