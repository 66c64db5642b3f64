// The build loop. Deciding what is stale (the action key and the cache lookup) and running a
// stage are both done per node inside its task, so independent nodes overlap completely;
// results are collected per node index and reported in topological order, so the summary
// and every output are identical whatever the thread count.
#include "pipeline/executor.h"

#include <fnmatch.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <mutex>
#include <set>
#include <thread>

#include "pipeline/graph.h"

namespace sylva {

namespace fs = std::filesystem;

const char* status_name(NodeStatus s) {
  switch (s) {
    case NodeStatus::kBuilt: return "built";
    case NodeStatus::kCached: return "cached";
    case NodeStatus::kFailed: return "failed";
    case NodeStatus::kSkipped: return "skipped";
    case NodeStatus::kInterrupted: return "interrupted";
    case NodeStatus::kWouldBuild: return "would-build";
    case NodeStatus::kUpToDate: return "up-to-date";
  }
  return "?";
}

std::size_t BuildSummary::count(NodeStatus s) const {
  return static_cast<std::size_t>(
      std::count_if(nodes.begin(), nodes.end(), [&](const NodeReport& r) { return r.status == s; }));
}

namespace {

// The StageContext a stage sees: everything it may touch, nothing else.
class NodeContext final : public StageContext {
 public:
  NodeContext(FileSystem& fs, const NodeDecl& node, std::vector<InputArtifact> inputs, fs::path scratch,
              fs::path out, const std::atomic<bool>* cancel)
      : fs_(fs), node_(node), inputs_(std::move(inputs)), scratch_(std::move(scratch)), out_(std::move(out)),
        cancel_(cancel) {
    auto it = node.params.find("seed");
    if (it != node.params.end() && it->second.is_int()) seed_ = static_cast<std::uint64_t>(it->second.as_int());
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
    if (!is_valid_name(name))
      throw std::logic_error("invalid output file name '" + std::string(name) + "'");
    declared_.insert(std::string(name));
    return out_ / std::string(name);
  }
  void write_output(std::string_view name, std::string_view bytes) override {
    // Not fsynced here: Cache::put_file syncs each output once, before it gets a trusted name.
    if (!fs_.write_atomic(output_path(name), bytes, /*durable=*/false))
      throw StageError("cannot write output '" + std::string(name) + "'");
  }
  void check_cancelled() const override {
    if (cancel_ && cancel_->load()) throw Cancelled();
  }
  const std::set<std::string>& declared() const { return declared_; }

 private:
  FileSystem& fs_;
  const NodeDecl& node_;
  std::vector<InputArtifact> inputs_;
  fs::path scratch_, out_;
  const std::atomic<bool>* cancel_;
  std::uint64_t seed_ = 0;
  std::set<std::string> declared_;
};

// Makes <node_dir> hold exactly `outputs`. A file DigestCache says still holds its digest is
// not read (the no-op case); one whose stat changed is hashed, and replaced from the CAS if its
// bytes differ (an edit in out/ never survives a build, and never reaches the CAS). `fresh`:
// the blobs were stored by this process just now, so they need no verification. False if a
// blob is missing or corrupt (the caller rebuilds).
bool publish(const BuildEnv& env, DigestCache& digests, const fs::path& node_dir,
             const std::vector<OutputEntry>& outputs, bool fresh) {
  std::string names;
  for (const auto& o : outputs) names += o.name + '\n';
  const Digest listing = digest_bytes(names);
  // The directory's own stat changes when an entry is added or removed: unchanged, it holds no
  // stray file and need not be listed.
  const bool dir_settled = digests.holds(node_dir, listing);
  if (!dir_settled) env.fs.make_dirs(node_dir);
  for (const auto& o : outputs) {
    const fs::path dest = node_dir / o.name;
    if (digests.holds(dest, o.digest)) continue;
    if (auto st = env.fs.stat(dest); st && !st->is_dir && st->size == o.digest.size) {
      const std::int64_t known_at = env.fs.now_ns();
      if (auto d = env.fs.digest(dest); d && *d == o.digest) {
        digests.record(dest, o.digest, known_at);
        continue;
      }
    }
    std::int64_t known_at = 0;
    if (!env.cache.materialize(o.digest, dest, !fresh, &known_at)) return false;
    digests.record(dest, o.digest, known_at);
  }
  if (!dir_settled) {
    std::set<std::string> keep;
    for (const auto& o : outputs) keep.insert(o.name);
    const std::int64_t known_at = env.fs.now_ns();
    for (const auto& name : env.fs.list(node_dir))
      if (!keep.count(name)) env.fs.remove_all(node_dir / name);
    // Settle the directory's mtime just below the clock read before it was listed (as
    // Cache::put_file does for blobs), so a file added later is always seen.
    env.fs.set_mtime(node_dir, known_at - 1);
    digests.record(node_dir, listing, known_at);
  }
  return true;
}

// The explain record is rewritten only when its action changed: a no-op build writes nothing.
void write_record(FileSystem& fs, DigestCache& digests, const fs::path& p, const std::string& node,
                  const std::string& key, const ActionRecord& action) {
  if (digests.note("record:" + node) == key) return;
  if (fs.write_atomic(p, action.to_json(), /*durable=*/false)) digests.set_note("record:" + node, key);
}

// The result a node last published into this out dir, kept with the digest records as
// "<key> <cache root>\n" then "<name> <hash> <size>\n" per output (ninja's build log: what
// each output was built from). A no-op with the same key and cache, whose files still hold
// these digests, is decided without reading the action cache.
std::string result_tag(const std::string& key, const Cache& cache) { return key + " " + cache.root().string(); }

std::string result_note(const std::string& tag, const std::vector<OutputEntry>& outputs) {
  std::string s = tag + "\n";
  for (const auto& o : outputs) s += o.name + " " + o.digest.hash + " " + std::to_string(o.digest.size) + "\n";
  return s;
}

std::optional<std::vector<OutputEntry>> published_result(DigestCache& digests, const std::string& node,
                                                         const std::string& key) {  // key: result_tag()
  auto note = digests.note("result:" + node);
  if (!note || note->compare(0, key.size(), key) != 0 || note->size() <= key.size() || (*note)[key.size()] != '\n')
    return std::nullopt;
  std::vector<OutputEntry> out;
  std::size_t at = key.size() + 1;
  while (at < note->size()) {
    const std::size_t end = note->find('\n', at);
    if (end == std::string::npos) return std::nullopt;
    const std::string line = note->substr(at, end - at);
    at = end + 1;
    const std::size_t a = line.find(' '), b = line.rfind(' ');
    if (a == std::string::npos || a == b) return std::nullopt;
    OutputEntry e{line.substr(0, a), {line.substr(a + 1, b - a - 1), 0}};
    try {
      e.digest.size = std::stoull(line.substr(b + 1));
    } catch (const std::exception&) {
      return std::nullopt;
    }
    if (!is_valid_name(e.name) || !is_hex_digest(e.digest.hash)) return std::nullopt;
    out.push_back(std::move(e));
  }
  return out;
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

}  // namespace

std::optional<ActionRecord> describe_action(const Recipe& recipe, std::size_t index,
                                            const std::vector<std::vector<OutputEntry>>& upstream,
                                            DigestCache& digests, std::string* error) {
  const NodeDecl& node = recipe.nodes[index];
  const StageInfo& info = node.stage->info();
  ActionRecord a;
  a.stage = info.name;
  a.version = info.version;
  for (const auto& [k, v] : node.params) a.params[k] = v.canonical();
  for (std::size_t k = 0; k < node.needs.size(); ++k) {
    const NodeDecl* up = recipe.find(node.needs[k]);
    ActionInput in{up->name, up->stage->info().output_type, {}};
    for (const auto& o : upstream[k]) in.files.emplace_back(o.name, o.digest);
    a.inputs.push_back(std::move(in));
  }
  for (const auto& [param, path] : node.files) {
    bool is_dir = false;
    for (const auto& p : info.params)
      if (p.name == param) is_dir = p.type == ParamType::kDir;
    auto d = is_dir ? digests.digest_dir(path) : digests.digest(path);
    if (!d) {
      if (error) *error = "cannot read '" + path.string() + "' (parameter '" + param + "')";
      return std::nullopt;
    }
    a.files[param] = {path.string(), *d};
    a.params[param] = "\"sha256:" + d->hash + "\"";  // content, not the path, enters the key
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
  if (env.observer) env.observer->on_plan(total);

  DigestCache digests(env.fs, env.out_dir / ".sylva" / "digests");
  digests.load();
  // Eviction (gc) waits while any build holds this; a dry run stores nothing and needs none.
  auto build_lock = options.dry_run ? nullptr : env.cache.lock_for_build();
  std::atomic<bool> stored_any{false};

  std::vector<NodeReport> reports(n);
  std::vector<std::vector<OutputEntry>> outputs(n);
  std::vector<std::atomic<int>> pending(n);
  std::atomic<bool> stop{false};
  std::mutex observer_mu;

  auto cancelled = [&] { return env.cancel && env.cancel->load(); };
  auto notify_start = [&](const std::string& name) {
    if (!env.observer) return;
    std::lock_guard lock(observer_mu);
    env.observer->on_start(name);
  };
  auto finish = [&](std::size_t i) {
    if (!env.observer) return;
    std::lock_guard lock(observer_mu);
    env.observer->on_finish(reports[i]);
  };

  // Runs (or skips) node i; its report and outputs are written to slot i only.
  auto process = [&](std::size_t i) {
    const NodeDecl& node = recipe.nodes[i];
    NodeReport& r = reports[i];
    r.name = node.name;
    r.stage = node.stage->info().name;
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
    std::vector<std::vector<OutputEntry>> upstream;
    for (const auto& up : node.needs) upstream.push_back(outputs[recipe.index_of(up)]);
    const double start = env.clock.now_seconds();
    std::string why;
    auto action = describe_action(recipe, i, upstream, digests, &why);
    if (!action) {
      r.status = NodeStatus::kFailed;
      r.error = why;
      return;
    }
    r.key = action->key();
    const fs::path node_dir = env.out_dir / node.name;
    const fs::path record = env.out_dir / ".sylva" / (node.name + ".json");

    if (options.dry_run) {
      auto hit = env.cache.lookup(r.key);
      r.status = hit ? NodeStatus::kUpToDate : NodeStatus::kWouldBuild;
      if (hit) outputs[i] = hit->outputs;
      return;
    }

    auto finish_cached = [&](const std::vector<OutputEntry>& result) {
      r.status = NodeStatus::kCached;
      r.outputs = outputs[i] = result;
      write_record(env.fs, digests, record, node.name, r.key, *action);
      digests.set_note("result:" + node.name, result_note(result_tag(r.key, env.cache), result));
      r.seconds = env.clock.now_seconds() - start;
    };
    auto use_cached = [&]() -> bool {
      auto hit = env.cache.lookup(r.key);
      if (!hit || !publish(env, digests, node_dir, hit->outputs, false)) return false;
      finish_cached(hit->outputs);
      return true;
    };
    // The no-op: this out dir already holds the result of this very action, unchanged (stats
    // only; neither the action cache nor the CAS is read).
    if (auto mine = published_result(digests, node.name, result_tag(r.key, env.cache))) {
      bool settled = digests.holds(node_dir, digest_bytes([&] {
        std::string names;
        for (const auto& o : *mine) names += o.name + '\n';
        return names;
      }()));
      for (const auto& o : *mine) settled = settled && digests.holds(node_dir / o.name, o.digest);
      if (settled) {
        finish_cached(*mine);
        return;
      }
    }
    // Otherwise the action cache. This path takes no lock. On a miss, one process runs the
    // action at a time; the others wait for the lock and then find the result in the cache.
    if (use_cached()) return;
    auto lock = env.cache.lock_action(r.key);
    if (use_cached()) return;

    notify_start(node.name);
    const fs::path scratch = env.cache.make_scratch_dir();
    const fs::path out = scratch / "out";
    const fs::path work = scratch / "work";
    env.fs.make_dirs(out);
    env.fs.make_dirs(work);
    NodeContext ctx(env.fs, node, input_artifacts(recipe, env, i, upstream), work, out, env.cancel);
    try {
      node.stage->run(ctx);
      ctx.check_cancelled();
      ActionResult result;
      for (const auto& name : env.fs.list(out))
        if (!ctx.declared().count(name))
          throw StageError("stage wrote undeclared output file '" + name + "'");
      for (const auto& name : ctx.declared()) {
        auto st = env.fs.stat(out / name);
        if (!st || st->is_dir) throw StageError("stage declared output '" + name + "' but did not write it");
        auto d = env.cache.put_file(out / name);
        if (!d) throw StageError("cannot store output '" + name + "' in the cache at " + env.cache.root().string());
        result.outputs.push_back({name, *d});
        stored_any = true;
      }
      env.cache.store_action(r.key, result);
      if (!publish(env, digests, node_dir, result.outputs, true))
        throw StageError("cannot publish outputs to " + node_dir.string());
      write_record(env.fs, digests, record, node.name, r.key, *action);
      digests.set_note("result:" + node.name, result_note(result_tag(r.key, env.cache), result.outputs));
      r.status = NodeStatus::kBuilt;
      r.outputs = outputs[i] = result.outputs;
    } catch (const Cancelled&) {
      r.status = NodeStatus::kInterrupted;
    } catch (const StageError& e) {
      r.status = NodeStatus::kFailed;
      r.error = e.what();
    } catch (const std::exception& e) {
      r.status = NodeStatus::kFailed;
      r.error = std::string("internal error in stage '") + r.stage + "': " + e.what();
    }
    env.fs.remove_all(scratch);
    r.seconds = env.clock.now_seconds() - start;
    if (r.status == NodeStatus::kFailed && !options.keep_going) stop = true;
  };

  const int jobs = options.jobs > 0 ? options.jobs
                                    : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  // Allow -j above the core count (stages may wait on I/O); the arena caps concurrency.
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(jobs));
  tbb::task_arena arena(jobs);
  tbb::task_group group;
  std::function<void(std::size_t)> launch = [&](std::size_t i) {
    group.run([&, i] {
      process(i);
      finish(i);
      for (std::size_t d : graph.dependents(i))
        if (wanted[d] && pending[d].fetch_sub(1) == 1) launch(d);
    });
  };
  arena.execute([&] {
    for (std::size_t i = 0; i < n; ++i) {
      int count = 0;
      for (std::size_t j : graph.inputs(i)) count += wanted[j] ? 1 : 0;
      pending[i].store(count);
    }
    // Roots are chosen before any task starts: a fast task could otherwise bring a dependent's
    // count to zero while this loop is still looking, and that node would run twice.
    std::vector<std::size_t> roots;
    for (std::size_t i : graph.topo_order())
      if (wanted[i] && pending[i].load() == 0) roots.push_back(i);
    for (std::size_t i : roots) launch(i);
    group.wait();
  });

  BuildSummary summary;
  for (std::size_t i : graph.topo_order())
    if (wanted[i]) summary.nodes.push_back(std::move(reports[i]));
  if (!digests.save()) summary.warning = "cannot write " + (env.out_dir / ".sylva" / "digests").string();

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
      if (i == target) lines.push_back("'" + node + "' will rebuild because its input '" + stale_input + "' will rebuild");
      continue;
    }
    std::string why;
    auto action = describe_action(recipe, i, upstream, digests, &why);
    if (!action) {
      if (i == target) lines.push_back("'" + node + "' cannot be planned: " + why);
      continue;
    }
    if (auto hit = env.cache.lookup(action->key())) {
      outputs[i] = hit->outputs;
      if (i == target) lines.push_back("'" + node + "' is up to date (action " + action->key().substr(0, 12) + " is cached)");
      continue;
    }
    if (i != target) continue;
    auto text = env.fs.read(env.out_dir / ".sylva" / (node + ".json"));
    auto before = text ? ActionRecord::from_json(*text) : std::nullopt;
    if (!before) {
      lines.push_back("'" + node + "' will build: no earlier build of it is recorded and action " +
                      action->key().substr(0, 12) + " is not in the cache");
      continue;
    }
    auto diffs = explain_difference(*before, *action);
    if (diffs.empty())
      lines.push_back("'" + node + "' will rebuild: its action is unchanged but its result is no longer in the cache");
    for (const auto& d : diffs) lines.push_back("'" + node + "' will rebuild: " + d);
  }
  return lines;
}

}  // namespace sylva
