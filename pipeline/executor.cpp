// The build loop. Deciding what is stale (the action key and the cache lookup) and running a
// stage are both done per node inside its task, so independent nodes overlap completely;
// results are collected per node index and reported in topological order, so the summary
// and every output are identical whatever the thread count.
#include "pipeline/executor.h"

#include <fcntl.h>
#include <fnmatch.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <set>
#include <streambuf>
#include <thread>

#include "pipeline/durable_batch.h"
#include "pipeline/graph.h"

namespace sylva {

namespace fs = std::filesystem;

const char* status_name(NodeStatus s) {
  switch (s) {
    case NodeStatus::kBuilt:
      return "built";
    case NodeStatus::kCached:
      return "cached";
    case NodeStatus::kFailed:
      return "failed";
    case NodeStatus::kSkipped:
      return "skipped";
    case NodeStatus::kInterrupted:
      return "interrupted";
    case NodeStatus::kWouldBuild:
      return "would-build";
    case NodeStatus::kUpToDate:
      return "up-to-date";
  }
  return "?";
}

std::size_t BuildSummary::count(NodeStatus s) const {
  return static_cast<std::size_t>(
      std::count_if(nodes.begin(), nodes.end(), [&](const NodeReport& r) { return r.status == s; }));
}

namespace {

// A streamed output: buffered writes to the scratch file, hashed on the way (StageContext::
// open_output). close() hands the digest to the context, so storing the output reads nothing.
class HashingStream final : public OutputStream, private std::streambuf {
 public:
  HashingStream(const fs::path& path, std::string name, std::map<std::string, Digest>* known, std::mutex* mu)
      : out_(this), path_(path), name_(std::move(name)), known_(known), mu_(mu), buf_(1 << 20) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) throw StageError("cannot create output '" + name_ + "': " + std::strerror(errno));
    setp(buf_.data(), buf_.data() + buf_.size());
  }
  ~HashingStream() override {
    if (fd_ >= 0) ::close(fd_);
  }
  std::ostream& stream() override { return out_; }
  void close() override {
    drain();
    int err = errno_;
    if (::close(fd_) != 0 && err == 0) err = errno;
    fd_ = -1;
    if (err != 0) throw StageError("cannot write output '" + name_ + "': " + std::strerror(err));
    std::lock_guard l(*mu_);
    (*known_)[name_] = Digest{hash_.finish_hex(), total_};
  }

 private:
  bool drain() {
    const std::size_t n = static_cast<std::size_t>(pptr() - pbase());
    const char* p = pbase();
    std::size_t left = n;
    while (left > 0 && errno_ == 0) {
      const ssize_t w = ::write(fd_, p, left);
      if (w < 0) {
        if (errno == EINTR) continue;
        errno_ = errno;
        break;
      }
      p += w;
      left -= static_cast<std::size_t>(w);
    }
    hash_.update(pbase(), n);
    total_ += n;
    setp(buf_.data(), buf_.data() + buf_.size());
    return errno_ == 0;
  }
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

  std::ostream out_;
  fs::path path_;
  std::string name_;
  std::map<std::string, Digest>* known_;
  std::mutex* mu_;
  std::vector<char> buf_;
  int fd_ = -1;
  int errno_ = 0;
  Sha256 hash_;
  std::uint64_t total_ = 0;
};

// The StageContext a stage sees: everything it may touch, nothing else.
class NodeContext final : public StageContext {
 public:
  NodeContext(FileSystem& fs, const NodeDecl& node, std::vector<InputArtifact> inputs, fs::path scratch,
              fs::path out, const std::atomic<bool>* cancel)
      : fs_(fs),
        node_(node),
        inputs_(std::move(inputs)),
        scratch_(std::move(scratch)),
        out_(std::move(out)),
        cancel_(cancel) {
    auto it = node.params.find("seed");
    if (it != node.params.end() && it->second.is_int())
      seed_ = static_cast<std::uint64_t>(it->second.as_int());
  }

  const std::string& node_name() const override { return node_.name; }
  const Value::Object& params() const override { return node_.params; }
  const std::vector<InputArtifact>& inputs() const override { return inputs_; }
  fs::path param_file(std::string_view param) const override {
    auto it = node_.files.find(std::string(param));
    if (it == node_.files.end())
      throw std::logic_error("stage asked for undeclared file parameter '" + std::string(param) + "'");
    return it->second;
  }
  Rng rng(std::string_view stream) const override { return Rng(seed_, stream); }
  const fs::path& scratch_dir() const override { return scratch_; }
  fs::path output_path(std::string_view name) override {
    const std::string n(name);
    if (!is_valid_name(name)) throw std::logic_error("invalid output file name '" + n + "'");
    if (!output_name_declared(n, node_.stage->info().outputs))
      throw std::logic_error("stage '" + node_.stage->info().name + "' wrote output '" + n +
                             "', which its StageInfo::outputs does not declare");
    std::lock_guard l(mu_);
    declared_.insert(n);
    known_.erase(n);  // whatever is written now must be hashed
    return out_ / n;
  }
  void write_output(std::string_view name, std::string_view bytes) override {
    // Not fsynced here: the DurableBatch syncs the file system before any result names it.
    const fs::path p = output_path(name);
    std::string why;
    if (!fs_.write_atomic(p, bytes, /*durable=*/false, &why))
      throw StageError("cannot write output '" + std::string(name) + "': " + why);
    std::lock_guard l(mu_);
    known_[std::string(name)] = digest_bytes(bytes);
  }
  std::unique_ptr<OutputStream> open_output(std::string_view name) override {
    const fs::path p = output_path(name);
    return std::make_unique<HashingStream>(p, std::string(name), &known_, &mu_);
  }
  void check_cancelled() const override {
    if (cancel_ && cancel_->load()) throw Cancelled();
  }
  const std::set<std::string>& declared() const { return declared_; }
  // The digest of output `name` if it was computed while writing it.
  std::optional<Digest> known_digest(const std::string& name) {
    std::lock_guard l(mu_);
    auto it = known_.find(name);
    if (it == known_.end()) return std::nullopt;
    return it->second;
  }

 private:
  FileSystem& fs_;
  const NodeDecl& node_;
  std::vector<InputArtifact> inputs_;
  fs::path scratch_, out_;
  const std::atomic<bool>* cancel_;
  std::uint64_t seed_ = 0;
  std::mutex mu_;
  std::set<std::string> declared_;
  std::map<std::string, Digest> known_;
};

bool same_names(const std::vector<OutputEntry>& a, const std::vector<OutputEntry>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](const OutputEntry& x, const OutputEntry& y) { return x.name == y.name; });
}

// True if <node_dir> still holds exactly what `p` says was published there: its directory's
// stat is unchanged (no file added or removed) and every file holds its digest (stats only).
bool still_published(const BuildEnv& env, DigestCache& digests, const fs::path& node_dir,
                     const PublishedNode& p) {
  auto st = env.fs.stat(node_dir);
  if (!st || !DigestCache::same_file(*st, p.dir)) return false;
  for (const auto& o : p.outputs)
    if (!digests.holds(node_dir / o.name, o.digest)) return false;
  return true;
}

// Makes <node_dir> hold exactly `outputs`, in one step: unless it already does (stats only, the
// no-op case), a new directory is assembled beside it (<out>/.<node>.tmp.*: hard links to the
// blobs, or to the files already there that still hold their digests) and swapped in, and the
// old one deleted. `fresh`: the blobs were stored by this process just now, so they need no
// verification; others are re-hashed first and a corrupt one is deleted. Returns the
// directory's stat, or nullopt (and `error`) if a blob is missing or corrupt or the disk
// refused (the caller rebuilds or fails).
std::optional<FileInfo> publish(const BuildEnv& env, DigestCache& digests, const std::string& node,
                                const fs::path& node_dir, const std::vector<OutputEntry>& outputs, bool fresh,
                                std::string* error) {
  auto prev = digests.published(node);
  if (prev && same_names(prev->outputs, outputs)) {
    PublishedNode now = *prev;
    now.outputs = outputs;
    if (still_published(env, digests, node_dir, now)) return prev->dir;
  }
  const fs::path staged = unique_temp_path(env.out_dir / ("." + node));
  // Entries added to it before this clock reading are older than its mtime set below; any
  // later change makes the directory's stat differ (the racy rule, as for blobs).
  const std::int64_t dir_known_at = env.fs.now_ns();
  auto abandon = [&](const std::string& why) -> std::optional<FileInfo> {
    env.fs.remove_all(staged);
    if (error) *error = why;
    return std::nullopt;
  };
  std::string why;
  if (!env.fs.make_dirs(staged, &why)) return abandon("cannot create " + staged.string() + ": " + why);
  std::vector<std::int64_t> known_at(outputs.size(), 0);
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const OutputEntry& o = outputs[k];
    const fs::path current = node_dir / o.name;
    if (digests.holds(current, o.digest)) {  // the file there is right: link it, unread
      known_at[k] = env.fs.now_ns();
      if (env.fs.link_or_copy(current, staged / o.name, nullptr, &why)) continue;
    }
    if (!env.cache.materialize(o.digest, staged / o.name, !fresh, &known_at[k], &why))
      return abandon("cannot publish " + o.name + ": " + why);
  }
  env.fs.set_mtime(staged, dir_known_at - 1);
  fs::path displaced;
  if (!env.fs.replace_dir(staged, node_dir, &displaced, &why))
    return abandon("cannot publish into " + node_dir.string() + ": " + why);
  if (!displaced.empty()) env.fs.remove_all(displaced);
  for (std::size_t k = 0; k < outputs.size(); ++k)
    digests.record(node_dir / outputs[k].name, outputs[k].digest, known_at[k]);
  auto st = env.fs.stat(node_dir);
  if (!st || !DigestCache::settled(st->mtime_ns, dir_known_at))
    return FileInfo{};  // published; not trusted next time
  return st;
}

// Where node `node`'s explain record (the action it was last built from) lives in the out dir.
fs::path explain_record_path(const BuildEnv& env, const std::string& node) {
  return env.out_dir / ".sylva" / (node + ".json");
}

// A node that could not be (re)built must not leave its old outputs under its name: they
// belong to another action. Moved aside in one rename, then deleted.
void withdraw(const BuildEnv& env, DigestCache& digests, const std::string& node, const fs::path& node_dir) {
  digests.forget_published(node);
  if (!env.fs.stat(node_dir)) return;
  const fs::path aside = unique_temp_path(env.out_dir / ("." + node));
  if (env.fs.rename(node_dir, aside))
    env.fs.remove_all(aside);
  else
    env.fs.remove_all(node_dir);
}

std::vector<InputArtifact> input_artifacts(const Recipe& recipe, const BuildEnv& env, std::size_t index,
                                           const std::vector<std::vector<OutputEntry>>& upstream) {
  const NodeDecl& node = recipe.nodes[index];
  std::vector<InputArtifact> out;
  for (std::size_t k = 0; k < node.needs.size(); ++k) {
    const NodeDecl* up = recipe.find(node.needs[k]);
    InputArtifact a{up->name, up->stage->info().output_type, {}};
    for (const auto& o : upstream[k])
      a.files.push_back({o.name, env.out_dir / up->name / o.name, o.digest.hash});
    out.push_back(std::move(a));
  }
  return out;
}

std::string what_of(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const std::exception& x) {
    return x.what();
  } catch (...) {
    return "an exception that is not a std::exception";
  }
}

}  // namespace

std::optional<ActionRecord> describe_action(const Recipe& recipe, std::size_t index,
                                            const std::vector<std::vector<OutputEntry>>& upstream,
                                            DigestCache& digests, std::string* error) {
  const NodeDecl& node = recipe.nodes[index];
  const StageInfo& info = node.stage->info();
  ActionRecord a;
  a.stage = info.name;
  a.version = info.version;
  for (const auto& [k, v] : node.params)
    if (!node.files.count(k)) a.params.emplace(k, v.canonical());
  for (std::size_t k = 0; k < node.needs.size(); ++k) {
    const NodeDecl* up = recipe.find(node.needs[k]);
    ActionInput in{up->name, up->stage->info().output_type, {}};
    in.files.reserve(upstream[k].size());
    for (const auto& o : upstream[k]) in.files.emplace_back(o.name, o.digest);
    a.inputs.push_back(std::move(in));
  }
  for (const auto& [param, path] : node.files) {
    bool is_dir = false;
    for (const auto& p : info.params)
      if (p.name == param) is_dir = p.type == ParamType::kDir;
    std::string why;
    std::optional<FileInfo> known;
    if (auto it = node.file_stats.find(param); it != node.file_stats.end()) known = it->second;
    auto d = is_dir ? digests.digest_dir(path, &why) : digests.digest(path, &why, known);
    if (!d) {
      if (error) *error = "cannot read '" + path.string() + "' (parameter '" + param + "'): " + why;
      return std::nullopt;
    }
    a.params[param] = "\"sha256:" + d->hash + "\"";  // content, not the path, enters the key
    a.files[param] = {path.string(), std::move(*d)};
  }
  return a;
}

BuildSummary run_build(const Recipe& recipe, const BuildEnv& env, const BuildOptions& options,
                       std::string* error) {
  const double t0 = env.clock.now_seconds();
  const BuildGraph graph(recipe);
  const std::size_t n = recipe.nodes.size();

  // Which nodes to build: targets and everything they need.
  std::vector<bool> wanted(n, options.targets.empty());
  if (!options.targets.empty()) {
    std::vector<std::size_t> roots;
    for (const auto& t : options.targets) {
      bool any = false;
      for (std::size_t i = 0; i < n; ++i)
        if (fnmatch(t.c_str(), recipe.nodes[i].name.c_str(), 0) == 0) {
          roots.push_back(i);
          any = true;
        }
      if (!any) {
        if (error) {
          std::vector<std::string> names;
          for (const auto& nd : recipe.nodes) names.push_back(nd.name);
          *error = "unknown target '" + t + "'" + did_you_mean(t, names);
        }
        return {};
      }
    }
    wanted = graph.closure(roots);
  }
  const std::size_t total = static_cast<std::size_t>(std::count(wanted.begin(), wanted.end(), true));

  DigestCache digests(env.fs, env.out_dir / ".sylva" / "digests");
  digests.load();
  // Eviction (gc) waits while any build holds this; a dry run stores nothing and needs none.
  auto build_lock = options.dry_run ? nullptr : env.cache.lock_for_build();
  DurableBatch batch(env.fs, env.cache);
  std::atomic<bool> stored_any{false};
  const std::string cache_tag = " " + env.cache.root().string();

  std::vector<NodeReport> reports(n);
  std::vector<std::vector<OutputEntry>> outputs(n);
  std::vector<std::atomic<int>> pending(n);
  std::atomic<bool> stop{false};
  std::mutex observer_mu, errors_mu;
  std::vector<std::string> errors;
  auto add_error = [&](std::string e) {
    std::lock_guard lock(errors_mu);
    errors.push_back(std::move(e));
  };

  auto cancelled = [&] { return env.cancel && env.cancel->load(); };
  // The observer is someone else's code: whatever it throws fails the node, never the build.
  auto observe = [&](NodeReport& r, auto&& call) {
    if (!env.observer) return;
    try {
      std::lock_guard lock(observer_mu);
      call();
    } catch (...) {
      r.status = NodeStatus::kFailed;
      r.error = "the build observer failed: " + what_of(std::current_exception());
    }
  };
  if (env.observer) {
    try {
      env.observer->on_plan(total);
    } catch (...) {
      errors.push_back("the build observer failed: " + what_of(std::current_exception()));
    }
  }

  // True (and node i reported cached) if this out dir holds the result of its current action,
  // unchanged: stats only, neither the action cache nor the CAS is read. Needs its inputs'
  // outputs; false when they are not known or anything differs.
  auto noop = [&](std::size_t i) -> bool {
    const NodeDecl& node = recipe.nodes[i];
    auto mine = digests.published(node.name);
    if (!mine) return false;
    const double start = env.clock.now_seconds();
    std::vector<std::vector<OutputEntry>> upstream;
    upstream.reserve(node.needs.size());
    for (const auto& up : node.needs) upstream.push_back(outputs[recipe.index_of(up)]);
    auto action = describe_action(recipe, i, upstream, digests, nullptr);
    if (!action) return false;
    std::string key = action->key();
    if (mine->tag.size() != key.size() + cache_tag.size() || mine->tag.compare(0, key.size(), key) != 0 ||
        mine->tag.compare(key.size(), std::string::npos, cache_tag) != 0)
      return false;
    if (!still_published(env, digests, env.out_dir / node.name, *mine)) return false;
    NodeReport& r = reports[i];
    r.name = node.name;
    r.stage = node.stage->info().name;
    r.key = std::move(key);
    r.status = NodeStatus::kCached;
    r.outputs = outputs[i] = std::move(mine->outputs);
    r.seconds = env.clock.now_seconds() - start;
    return true;
  };

  // Runs (or skips) node i; its report and outputs are written to slot i only.
  auto process = [&](std::size_t i) {
    const NodeDecl& node = recipe.nodes[i];
    const StageInfo& info = node.stage->info();
    NodeReport& r = reports[i];
    r.name = node.name;
    r.stage = info.name;
    for (std::size_t j : graph.inputs(i)) {
      const NodeStatus s = reports[j].status;
      if (s == NodeStatus::kWouldBuild && options.dry_run) {
        r.status = NodeStatus::kWouldBuild;
        r.error = "input '" + recipe.nodes[j].name + "' will be rebuilt";
        return;
      }
      if (s != NodeStatus::kBuilt && s != NodeStatus::kCached && s != NodeStatus::kUpToDate) {
        r.status = s == NodeStatus::kInterrupted ? NodeStatus::kInterrupted : NodeStatus::kSkipped;
        r.error = "input '" + recipe.nodes[j].name + "' " + status_name(s);
        return;
      }
    }
    if (cancelled()) {
      r.status = NodeStatus::kInterrupted;
      return;
    }
    if (stop.load()) {
      r.status = NodeStatus::kSkipped;
      r.error = "build stopped after a failure";
      return;
    }
    const fs::path node_dir = env.out_dir / node.name;
    std::vector<std::vector<OutputEntry>> upstream;
    upstream.reserve(node.needs.size());
    for (const auto& up : node.needs) upstream.push_back(outputs[recipe.index_of(up)]);
    const double start = env.clock.now_seconds();
    std::string why;
    auto action = describe_action(recipe, i, upstream, digests, &why);
    if (!action) {
      r.status = cancelled() ? NodeStatus::kInterrupted : NodeStatus::kFailed;
      r.error = why;
      if (r.status == NodeStatus::kFailed && !options.dry_run) withdraw(env, digests, node.name, node_dir);
      return;
    }
    r.key = action->key();
    const std::string tag = r.key + cache_tag;

    if (options.dry_run) {
      if (auto mine = digests.published(node.name); mine && mine->tag == tag) {
        r.status = NodeStatus::kUpToDate;
        outputs[i] = mine->outputs;
        return;
      }
      auto hit = env.cache.lookup(r.key, info.outputs);
      r.status = hit ? NodeStatus::kUpToDate : NodeStatus::kWouldBuild;
      if (hit) outputs[i] = hit->outputs;
      return;
    }

    // Remembers what this out dir now holds for the node, and writes its explain record if
    // its action changed (a no-op writes nothing).
    auto remember = [&](const std::vector<OutputEntry>& result, const FileInfo& dir) {
      auto prev = digests.published(node.name);
      PublishedNode p{tag, result, dir, prev ? prev->record_key : std::string()};
      if (p.record_key != r.key) {
        const fs::path record = explain_record_path(env, node.name);
        std::string werr;
        if (env.fs.write_atomic(record, action->to_json(), /*durable=*/false, &werr))
          p.record_key = r.key;
        else
          add_error("cannot write the explain record " + record.string() + ": " + werr);
      }
      digests.set_published(node.name, std::move(p));
    };
    auto finish_cached = [&](const std::vector<OutputEntry>& result, const FileInfo& dir) {
      r.status = NodeStatus::kCached;
      r.outputs = outputs[i] = result;
      remember(result, dir);
      r.seconds = env.clock.now_seconds() - start;
    };
    // The no-op: this out dir already holds the result of this very action, unchanged (stats
    // only; neither the action cache nor the CAS is read).
    if (auto mine = digests.published(node.name);
        mine && mine->tag == tag && still_published(env, digests, node_dir, *mine)) {
      r.status = NodeStatus::kCached;
      r.outputs = outputs[i] = mine->outputs;
      r.seconds = env.clock.now_seconds() - start;
      return;
    }
    auto use_cached = [&]() -> bool {
      auto hit = env.cache.lookup(r.key, info.outputs);
      if (!hit) return false;
      std::string perr;
      auto dir = publish(env, digests, node.name, node_dir, hit->outputs, false, &perr);
      if (!dir) return false;  // a blob went missing or was corrupt: rebuild
      finish_cached(hit->outputs, *dir);
      return true;
    };
    // Otherwise the action cache. This path takes no lock. On a miss, one process runs the
    // action at a time; the others wait for the lock and then find the result in the cache.
    if (use_cached()) return;
    auto lock = env.cache.lock_action(r.key);
    if (use_cached()) return;

    observe(r, [&] { env.observer->on_start(node.name); });
    if (r.status == NodeStatus::kFailed) {
      withdraw(env, digests, node.name, node_dir);
      return;
    }
    const fs::path scratch = env.cache.make_scratch_dir();
    const fs::path out = scratch / "out";
    const fs::path work = scratch / "work";
    env.fs.make_dirs(out);
    env.fs.make_dirs(work);
    NodeContext ctx(env.fs, node, input_artifacts(recipe, env, i, upstream), work, out, env.cancel);
    try {
      // Isolated: while this thread waits inside the stage's own parallel loops it runs only
      // their tasks, never another node (which could wait for the action lock held here).
      tbb::this_task_arena::isolate([&] { node.stage->run(ctx); });
      ctx.check_cancelled();
      ActionResult result;
      for (const auto& name : env.fs.list(out))
        if (!ctx.declared().count(name))
          throw StageError("stage wrote undeclared output file '" + name + "'");
      if (ctx.declared().empty()) throw StageError("stage wrote no output");
      for (const auto& name : ctx.declared()) {
        auto st = env.fs.stat(out / name);
        if (!st || st->is_dir || st->is_other)
          throw StageError("stage declared output '" + name + "' but did not write it");
        std::string perr;
        auto known = ctx.known_digest(name);
        if (known && known->size != st->size) known.reset();  // rewritten behind the API's back
        auto d = env.cache.put_file(out / name, nullptr, /*durable=*/false, &perr, known);
        if (!d) {
          ctx.check_cancelled();
          throw StageError("cannot store output '" + name + "' in the cache at " + env.cache.root().string() +
                           ": " + perr);
        }
        result.outputs.push_back({name, *d});
        stored_any = true;
      }
      std::string perr;
      auto dir = publish(env, digests, node.name, node_dir, result.outputs, true, &perr);
      if (!dir) throw StageError(perr);
      // Written once the blobs are durable; the lock goes with it, so a concurrent build
      // waiting for it finds the result.
      batch.commit(r.key, result, std::move(lock));
      remember(result.outputs, *dir);
      r.status = NodeStatus::kBuilt;
      r.outputs = outputs[i] = result.outputs;
    } catch (const Cancelled&) {
      r.status = NodeStatus::kInterrupted;
    } catch (const StageError& e) {
      r.status = NodeStatus::kFailed;
      r.error = e.what();
    } catch (...) {
      r.status = cancelled() ? NodeStatus::kInterrupted : NodeStatus::kFailed;
      r.error =
          std::string("internal error in stage '") + r.stage + "': " + what_of(std::current_exception());
    }
    env.fs.remove_all(scratch);
    if (r.status == NodeStatus::kFailed) withdraw(env, digests, node.name, node_dir);
    r.seconds = env.clock.now_seconds() - start;
  };

  // First, on this thread and in build order, every node that is a no-op (its inputs are, and
  // this out dir holds its action's result unchanged: stats only). A no-op build ends here,
  // without starting oneTBB's threads; otherwise only the rest is scheduled.
  std::vector<bool> decided(n, false);
  std::size_t undecided = 0;
  for (std::size_t i : graph.topo_order()) {
    if (!wanted[i]) continue;
    bool inputs_done = true;
    for (std::size_t j : graph.inputs(i)) inputs_done = inputs_done && decided[j];
    if (!options.dry_run && inputs_done && !cancelled() && noop(i)) {
      decided[i] = true;
      observe(reports[i], [&] { env.observer->on_finish(reports[i]); });
    } else {
      ++undecided;
    }
  }

  if (undecided > 0) {
    const int jobs =
        options.jobs > 0 ? options.jobs : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    // Allow -j above the core count (stages may wait on I/O); the arena caps concurrency.
    tbb::global_control allow(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(jobs));
    tbb::task_arena arena(jobs);
    tbb::task_group group;
    std::function<void(std::size_t)> launch = [&](std::size_t i) {
      group.run([&, i] {
        NodeReport& r = reports[i];
        try {
          process(i);
        } catch (...) {  // nothing escapes into oneTBB (it would terminate the process)
          r.status = NodeStatus::kFailed;
          r.error = "internal error: " + what_of(std::current_exception());
        }
        if (r.status == NodeStatus::kFailed && !options.keep_going) stop = true;
        observe(r, [&] { env.observer->on_finish(r); });
        for (std::size_t d : graph.dependents(i))
          if (wanted[d] && !decided[d] && pending[d].fetch_sub(1) == 1) launch(d);
      });
    };
    arena.execute([&] {
      for (std::size_t i = 0; i < n; ++i) {
        int count = 0;
        for (std::size_t j : graph.inputs(i)) count += wanted[j] && !decided[j] ? 1 : 0;
        pending[i].store(count);
      }
      // Roots are chosen before any task starts: a fast task could otherwise bring a dependent's
      // count to zero while this loop is still looking, and that node would run twice.
      std::vector<std::size_t> roots;
      for (std::size_t i : graph.topo_order())
        if (wanted[i] && !decided[i] && pending[i].load() == 0) roots.push_back(i);
      for (std::size_t i : roots) launch(i);
      group.wait();
    });
  }

  std::vector<std::string> batch_errors;
  if (!batch.finish(&batch_errors)) errors.insert(errors.end(), batch_errors.begin(), batch_errors.end());
  BuildSummary summary;
  for (std::size_t i : graph.topo_order())
    if (wanted[i]) summary.nodes.push_back(std::move(reports[i]));
  // Nodes this out dir holds outputs of that the recipe no longer declares (removed or renamed):
  // their directories go as a failed node's do, so nothing under out/<recipe>/ outlives its
  // node (ninja leaves such files until `ninja -t cleandead`; an asset pack must not ship them).
  // Only what the records say this out dir published is touched.
  std::set<std::string> declared;
  for (const auto& nd : recipe.nodes) declared.insert(nd.name);
  for (const std::string& name : digests.published_nodes()) {
    // A damaged records file must not name a path outside the node directories.
    if (declared.contains(name) || !is_valid_name(name) || name.front() == '.') continue;
    summary.removed.push_back(name);
    if (options.dry_run) continue;
    withdraw(env, digests, name, env.out_dir / name);
    env.fs.remove(explain_record_path(env, name));
  }
  std::string why;
  if (!options.dry_run) digests.settle_links();
  if (!options.dry_run && !digests.save(&why))
    errors.push_back("cannot write " + (env.out_dir / ".sylva" / "digests").string() + ": " + why);
  summary.errors = std::move(errors);

  // Automatic eviction, only after a build that added blobs, and only when no other build is
  // running (they hold the lock shared; the next build to finish alone will do it).
  build_lock.reset();
  if (stored_any && options.cache_max_bytes.value_or(1) > 0) {
    if (auto gc_lock = env.cache.try_lock_for_gc()) {
      const std::uint64_t held = env.cache.blob_bytes();
      const std::uint64_t limit = options.cache_max_bytes.value_or(static_cast<std::uint64_t>(
          kDefaultCacheShare * static_cast<double>(env.fs.free_bytes(env.cache.root()).value_or(0) + held)));
      if (limit > 0 && held > limit) summary.evicted = env.cache.gc(limit);
    }
  }
  summary.seconds = env.clock.now_seconds() - t0;
  return summary;
}

std::vector<std::string> explain_node(const Recipe& recipe, const BuildEnv& env, const std::string& node) {
  DigestCache digests(env.fs, env.out_dir / ".sylva" / "digests");
  digests.load();
  const std::size_t target = recipe.index_of(node);
  const BuildGraph graph(recipe);
  const auto wanted = graph.closure({target});
  std::vector<std::optional<std::vector<OutputEntry>>> outputs(recipe.nodes.size());
  std::vector<std::string> lines;
  for (std::size_t i : graph.topo_order()) {
    if (!wanted[i]) continue;
    const NodeDecl& nd = recipe.nodes[i];
    std::vector<std::vector<OutputEntry>> upstream;
    std::string stale_input;
    for (const auto& up : nd.needs) {
      const auto& o = outputs[recipe.index_of(up)];
      if (!o) stale_input = up;
      upstream.push_back(o.value_or(std::vector<OutputEntry>{}));
    }
    if (!stale_input.empty()) {
      if (i == target)
        lines.push_back("'" + node + "' will rebuild because its input '" + stale_input + "' will rebuild");
      continue;
    }
    std::string why;
    auto action = describe_action(recipe, i, upstream, digests, &why);
    if (!action) {
      if (i == target) lines.push_back("'" + node + "' cannot be planned: " + why);
      continue;
    }
    if (auto hit = env.cache.lookup(action->key(), nd.stage->info().outputs)) {
      outputs[i] = hit->outputs;
      if (i == target)
        lines.push_back("'" + node + "' is up to date (action " + action->key().substr(0, 12) +
                        " is cached)");
      continue;
    }
    if (i != target) continue;
    auto text = env.fs.read(explain_record_path(env, node), nullptr, kMaxActionBytes);
    auto before = text ? ActionRecord::from_json(*text) : std::nullopt;
    if (!before) {
      lines.push_back("'" + node + "' will build: no earlier build of it is recorded and action " +
                      action->key().substr(0, 12) + " is not in the cache");
      continue;
    }
    auto diffs = explain_difference(*before, *action);
    if (diffs.empty())
      lines.push_back("'" + node +
                      "' will rebuild: its action is unchanged but its result is no longer in the cache");
    for (const auto& d : diffs) lines.push_back("'" + node + "' will rebuild: " + d);
  }
  return lines;
}

}  // namespace sylva
