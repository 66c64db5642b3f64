// The build loop. Deciding what is stale (the action key, the out dir's records, the action
// cache) and running a stage are both done per node inside its task, so independent nodes overlap
// completely; results are collected per node index and reported in topological order, so the
// summary and every output are identical whatever the thread count. The pieces it wires:
// plan_build (which nodes), run_in_dependency_order (when), OutDir (publishing), ActionCache and
// BlobStore (the cache's seams), NodeRunner (running a stale node), DurableBatch (durability).
#include "pipeline/executor.h"

#include <algorithm>
#include <mutex>
#include <set>

#include "pipeline/durable_batch.h"
#include "pipeline/graph.h"
#include "pipeline/local_runner.h"
#include "pipeline/out_dir.h"
#include "pipeline/plan.h"
#include "pipeline/scheduler.h"

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

std::string what_of(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const std::exception& x) {
    return x.what();
  } catch (...) {
    return "an exception that is not a std::exception";
  }
}

// One run of the build loop over a planned recipe.
class Build {
 public:
  Build(const Recipe& recipe, const BuildEnv& env, const BuildOptions& options, const BuildGraph& graph,
        BuildPlan plan, NodeRunner& runner)
      : recipe_(recipe),
        env_(env),
        options_(options),
        graph_(graph),
        plan_(std::move(plan)),
        actions_(env.actions ? *env.actions : env.cache),
        blobs_(env.blobs ? *env.blobs : env.cache),
        runner_(runner),
        writes_(runner.executes()),
        out_(env.fs, blobs_, env.out_dir),
        batch_(actions_, blobs_),
        cache_tag_(" " + env.cache.root().string()),
        reports_(recipe.nodes.size()),
        outputs_(recipe.nodes.size()) {}

  BuildSummary run();

 private:
  bool cancelled() const { return env_.cancel && env_.cancel->load(); }
  void add_error(std::string e) {
    std::lock_guard lock(errors_mu_);
    errors_.push_back(std::move(e));
  }
  // The observer is someone else's code: whatever it throws fails the node, never the build.
  template <class Call>
  void observe(NodeReport& r, Call&& call) {
    if (!env_.observer) return;
    try {
      std::lock_guard lock(observer_mu_);
      call();
    } catch (...) {
      r.status = NodeStatus::kFailed;
      r.error = "the build observer failed: " + what_of(std::current_exception());
    }
  }
  std::vector<std::vector<OutputEntry>> upstream(std::size_t i) const;
  std::vector<InputArtifact> input_artifacts(std::size_t i,
                                             const std::vector<std::vector<OutputEntry>>& up) const;
  bool settle_noop(std::size_t i);
  void process(std::size_t i);
  bool inputs_usable(std::size_t i, NodeReport& r);
  void build_node(std::size_t i, NodeReport& r);
  bool reuse_cached(std::size_t i, NodeReport& r, const ActionRecord& action, const std::string& tag);
  void run_node(std::size_t i, NodeReport& r, const ActionRecord& action, const std::string& tag,
                std::vector<std::vector<OutputEntry>> up);
  void remember(std::size_t i, const NodeReport& r, const ActionRecord& action, const std::string& tag,
                const std::vector<OutputEntry>& result, const FileInfo& dir);
  void remove_dropped_nodes(BuildSummary& summary);
  void evict_if_needed(BuildSummary& summary);

  const Recipe& recipe_;
  const BuildEnv& env_;
  const BuildOptions& options_;
  const BuildGraph& graph_;
  const BuildPlan plan_;
  ActionCache& actions_;
  BlobStore& blobs_;
  NodeRunner& runner_;
  const bool writes_;  // false for a dry run: nothing is published, withdrawn, recorded or locked
  OutDir out_;
  DurableBatch batch_;
  const std::string cache_tag_;  // which cache a published node's action came from
  std::vector<NodeReport> reports_;
  std::vector<std::vector<OutputEntry>> outputs_;
  std::atomic<bool> stop_{false}, stored_any_{false};
  std::mutex observer_mu_, errors_mu_;
  std::vector<std::string> errors_;
};

std::vector<std::vector<OutputEntry>> Build::upstream(std::size_t i) const {
  const NodeDecl& node = recipe_.nodes[i];
  std::vector<std::vector<OutputEntry>> up;
  up.reserve(node.needs.size());
  for (const auto& name : node.needs) up.push_back(outputs_[recipe_.index_of(name)]);
  return up;
}

std::vector<InputArtifact> Build::input_artifacts(std::size_t i,
                                                  const std::vector<std::vector<OutputEntry>>& up) const {
  const NodeDecl& node = recipe_.nodes[i];
  std::vector<InputArtifact> out;
  for (std::size_t k = 0; k < node.needs.size(); ++k) {
    const NodeDecl* in = recipe_.find(node.needs[k]);
    InputArtifact a{in->name, in->stage->info().output_type, {}};
    for (const auto& o : up[k])
      a.files.push_back({o.name, out_.node_dir(in->name) / o.name, o.digest.hash, o.digest.size});
    out.push_back(std::move(a));
  }
  return out;
}

// True (and node i reported cached) if this out dir holds the result of its current action,
// unchanged: stats only, neither the action cache nor the CAS is read. Needs its inputs'
// outputs; false when they are not known or anything differs.
bool Build::settle_noop(std::size_t i) {
  const NodeDecl& node = recipe_.nodes[i];
  auto mine = out_.digests().published(node.name);
  if (!mine) return false;
  const double start = env_.clock.now_seconds();
  auto action = describe_action(recipe_, i, upstream(i), out_.digests(), nullptr);
  if (!action) return false;
  std::string key = action->key();
  if (mine->tag.size() != key.size() + cache_tag_.size() || mine->tag.compare(0, key.size(), key) != 0 ||
      mine->tag.compare(key.size(), std::string::npos, cache_tag_) != 0)
    return false;
  if (!out_.holds(node.name, *mine)) return false;
  NodeReport& r = reports_[i];
  r.name = node.name;
  r.stage = node.stage->info().name;
  r.key = std::move(key);
  r.status = NodeStatus::kCached;
  r.outputs = outputs_[i] = std::move(mine->outputs);
  r.seconds = env_.clock.now_seconds() - start;
  return true;
}

// Runs (or skips) node i; its report and outputs are written to slot i only. Never throws.
void Build::process(std::size_t i) {
  NodeReport& r = reports_[i];
  try {
    r.name = recipe_.nodes[i].name;
    r.stage = recipe_.nodes[i].stage->info().name;
    if (inputs_usable(i, r)) build_node(i, r);
  } catch (...) {  // nothing escapes into oneTBB (it would terminate the process)
    r.status = NodeStatus::kFailed;
    r.error = "internal error: " + what_of(std::current_exception());
  }
  if (r.status == NodeStatus::kFailed && !options_.keep_going) stop_ = true;
  observe(r, [&] { env_.observer->on_finish(r); });
}

// False (and r says why) if node i cannot be built: an input failed, was skipped or interrupted,
// will be rebuilt (dry run), or the build is stopping.
bool Build::inputs_usable(std::size_t i, NodeReport& r) {
  for (std::size_t j : graph_.inputs(i)) {
    const NodeStatus s = reports_[j].status;
    if (s == NodeStatus::kWouldBuild) {
      r.status = NodeStatus::kWouldBuild;
      r.error = "input '" + recipe_.nodes[j].name + "' will be rebuilt";
      return false;
    }
    if (s != NodeStatus::kBuilt && s != NodeStatus::kCached && s != NodeStatus::kUpToDate) {
      r.status = s == NodeStatus::kInterrupted ? NodeStatus::kInterrupted : NodeStatus::kSkipped;
      r.error = "input '" + recipe_.nodes[j].name + "' " + status_name(s);
      return false;
    }
  }
  if (cancelled()) {
    r.status = NodeStatus::kInterrupted;
    return false;
  }
  if (stop_.load()) {
    r.status = NodeStatus::kSkipped;
    r.error = "build stopped after a failure";
    return false;
  }
  return true;
}

// The node's action, then the first of: this out dir already holds its result (the no-op,
// stats only); the action cache has it; the runner runs it.
void Build::build_node(std::size_t i, NodeReport& r) {
  const NodeDecl& node = recipe_.nodes[i];
  const double start = env_.clock.now_seconds();
  auto up = upstream(i);
  std::string why;
  auto action = describe_action(recipe_, i, up, out_.digests(), &why);
  if (!action) {
    r.status = cancelled() ? NodeStatus::kInterrupted : NodeStatus::kFailed;
    r.error = why;
    if (r.status == NodeStatus::kFailed && writes_) out_.withdraw(node.name);
    return;
  }
  r.key = action->key();
  const std::string tag = r.key + cache_tag_;
  if (auto mine = out_.digests().published(node.name);
      mine && mine->tag == tag && out_.holds(node.name, *mine)) {
    r.status = writes_ ? NodeStatus::kCached : NodeStatus::kUpToDate;
    r.outputs = outputs_[i] = mine->outputs;
  } else if (!reuse_cached(i, r, *action, tag)) {
    run_node(i, r, *action, tag, std::move(up));
  }
  r.seconds = env_.clock.now_seconds() - start;
}

// True (and node i reported cached, or up to date in a dry run) if the action cache has the
// result and it could be published. This path takes no lock.
bool Build::reuse_cached(std::size_t i, NodeReport& r, const ActionRecord& action, const std::string& tag) {
  const NodeDecl& node = recipe_.nodes[i];
  auto hit = actions_.lookup(r.key, node.stage->info().outputs);
  if (!hit) return false;
  if (!writes_) {
    r.status = NodeStatus::kUpToDate;
    r.outputs = outputs_[i] = hit->outputs;
    return true;
  }
  std::string why;
  auto dir = out_.publish(node.name, hit->outputs, /*fresh=*/false, &why);
  if (!dir) return false;  // a blob went missing or was corrupt: rebuild
  r.status = NodeStatus::kCached;
  r.outputs = outputs_[i] = hit->outputs;
  remember(i, r, action, tag, hit->outputs, *dir);
  return true;
}

// On a miss, one process runs the action at a time; the others wait for the action lock and
// then find the result in the cache.
void Build::run_node(std::size_t i, NodeReport& r, const ActionRecord& action, const std::string& tag,
                     std::vector<std::vector<OutputEntry>> up) {
  const NodeDecl& node = recipe_.nodes[i];
  std::unique_ptr<FileLock> lock;
  if (writes_) {
    lock = env_.cache.lock_action(r.key);
    if (reuse_cached(i, r, action, tag)) return;
    observe(r, [&] { env_.observer->on_start(node.name); });
    if (r.status == NodeStatus::kFailed) {
      out_.withdraw(node.name);
      return;
    }
  }
  try {
    NodeRun run = runner_.run(NodeJob{node, r.key, input_artifacts(i, up)});
    if (!run.executed) {
      r.status = NodeStatus::kWouldBuild;
      return;
    }
    stored_any_ = true;
    std::string why;
    auto dir = out_.publish(node.name, run.result.outputs, /*fresh=*/true, &why);
    if (!dir) throw StageError(why);
    // Written once the blobs are durable; the lock goes with it, so a concurrent build waiting
    // for it finds the result.
    batch_.commit(r.key, run.result, std::move(lock));
    remember(i, r, action, tag, run.result.outputs, *dir);
    r.status = NodeStatus::kBuilt;
    r.outputs = outputs_[i] = std::move(run.result.outputs);
  } catch (const Cancelled&) {
    r.status = NodeStatus::kInterrupted;
  } catch (const StageError& e) {
    r.status = NodeStatus::kFailed;
    r.error = e.what();
  } catch (...) {
    r.status = cancelled() ? NodeStatus::kInterrupted : NodeStatus::kFailed;
    r.error = std::string("internal error in stage '") + r.stage + "': " + what_of(std::current_exception());
  }
  if (r.status == NodeStatus::kFailed) out_.withdraw(node.name);
}

// Remembers what this out dir now holds for node i, and writes its explain record if its action
// changed (a no-op writes nothing).
void Build::remember(std::size_t i, const NodeReport& r, const ActionRecord& action, const std::string& tag,
                     const std::vector<OutputEntry>& result, const FileInfo& dir) {
  const std::string& name = recipe_.nodes[i].name;
  auto prev = out_.digests().published(name);
  PublishedNode p{tag, result, dir, prev ? prev->record_key : std::string()};
  if (p.record_key != r.key) {
    const fs::path record = out_.explain_record(name);
    std::string why;
    if (env_.fs.write_atomic(record, action.to_json(), /*durable=*/false, &why))
      p.record_key = r.key;
    else
      add_error("cannot write the explain record " + record.string() + ": " + why);
  }
  out_.digests().set_published(name, std::move(p));
}

// Nodes this out dir holds outputs of that the recipe no longer declares (removed or renamed):
// their directories go as a failed node's do, so nothing under out/<recipe>/ outlives its node
// (ninja leaves such files until `ninja -t cleandead`; an asset pack must not ship them). Only
// what the records say this out dir published is touched.
void Build::remove_dropped_nodes(BuildSummary& summary) {
  std::set<std::string> declared;
  for (const auto& nd : recipe_.nodes) declared.insert(nd.name);
  for (const std::string& name : out_.digests().published_nodes()) {
    // A damaged records file must not name a path outside the node directories.
    if (declared.contains(name) || !is_valid_name(name) || name.front() == '.') continue;
    summary.removed.push_back(name);
    if (!writes_) continue;
    out_.withdraw(name);
    env_.fs.remove(out_.explain_record(name));
  }
}

// Automatic eviction, only after a build that added blobs, and only when no other build is
// running (they hold the lock shared; the next build to finish alone will do it).
void Build::evict_if_needed(BuildSummary& summary) {
  if (!stored_any_ || options_.cache_max_bytes.value_or(1) == 0) return;
  auto gc_lock = env_.cache.try_lock_for_gc();
  if (!gc_lock) return;
  const std::uint64_t held = env_.cache.blob_bytes();
  const std::uint64_t limit = options_.cache_max_bytes.value_or(static_cast<std::uint64_t>(
      kDefaultCacheShare * static_cast<double>(env_.fs.free_bytes(env_.cache.root()).value_or(0) + held)));
  if (limit > 0 && held > limit) summary.evicted = env_.cache.gc(limit);
}

BuildSummary Build::run() {
  const double t0 = env_.clock.now_seconds();
  // Eviction (gc) waits while any build holds this; a dry run stores nothing and needs none.
  auto build_lock = writes_ ? env_.cache.lock_for_build() : nullptr;
  if (env_.observer) {
    try {
      env_.observer->on_plan(plan_.total);
    } catch (...) {
      errors_.push_back("the build observer failed: " + what_of(std::current_exception()));
    }
  }
  // First, on this thread and in build order, every node that is a no-op (its inputs are, and
  // this out dir holds its action's result unchanged: stats only). A no-op build ends here,
  // without starting oneTBB's threads; otherwise only the rest is scheduled.
  std::vector<bool> todo = plan_.wanted;
  std::vector<bool> decided(recipe_.nodes.size(), false);
  for (std::size_t i : graph_.topo_order()) {
    if (!plan_.wanted[i]) continue;
    bool inputs_done = true;
    for (std::size_t j : graph_.inputs(i)) inputs_done = inputs_done && decided[j];
    if (writes_ && inputs_done && !cancelled() && settle_noop(i)) {
      decided[i] = true;
      todo[i] = false;
      observe(reports_[i], [&] { env_.observer->on_finish(reports_[i]); });
    }
  }
  run_in_dependency_order(graph_, todo, options_.jobs, [this](std::size_t i) { process(i); });

  std::vector<std::string> batch_errors;
  if (!batch_.finish(&batch_errors)) errors_.insert(errors_.end(), batch_errors.begin(), batch_errors.end());
  BuildSummary summary;
  for (std::size_t i : graph_.topo_order())
    if (plan_.wanted[i]) summary.nodes.push_back(std::move(reports_[i]));
  remove_dropped_nodes(summary);
  std::string why;
  if (writes_) {
    out_.digests().settle_links();
    if (!out_.digests().save(&why))
      errors_.push_back("cannot write " + (env_.out_dir / ".sylva" / "digests").string() + ": " + why);
  }
  summary.errors = std::move(errors_);
  build_lock.reset();
  evict_if_needed(summary);
  summary.seconds = env_.clock.now_seconds() - t0;
  return summary;
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
    const ParamSpec* spec = nullptr;
    for (const auto& p : info.params)
      if (p.name == param) spec = &p;
    const bool is_dir = spec && spec->type == ParamType::kDir;
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
    // A model file's folder (ParamSpec::with_folder_for): its companions are inputs too. Recorded
    // as file "<param>.folder" (not a parameter name: those have no dot), so explain names it.
    if (auto folder = spec ? param_folder(*spec, path) : std::nullopt) {
      auto fd = digests.digest_dir(*folder, &why, kMaxFolderFiles);
      if (!fd) {
        if (error)
          *error = "cannot read the folder '" + folder->string() + "' of '" + path.string() +
                   "' (parameter '" + param + "'): " + why + "; a " + path.extension().string() +
                   " file brings its whole folder into the node's key: give the model a folder of its own";
        return std::nullopt;
      }
      a.files[param + ".folder"] = {folder->string(), std::move(*fd)};
    }
  }
  return a;
}

BuildSummary run_build(const Recipe& recipe, const BuildEnv& env, const BuildOptions& options,
                       std::string* error) {
  const BuildGraph graph(recipe);
  auto plan = plan_build(recipe, graph, options.targets, error);
  if (!plan) return {};
  BlobStore& blobs = env.blobs ? *env.blobs : env.cache;
  LocalRunner local(env.fs, env.cache, blobs, env.cancel);
  DryRunRunner dry;
  NodeRunner& runner = options.dry_run ? static_cast<NodeRunner&>(dry) : env.runner ? *env.runner : local;
  return Build(recipe, env, options, graph, std::move(*plan), runner).run();
}

}  // namespace sylva
