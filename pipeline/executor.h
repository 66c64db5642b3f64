// Runs a checked recipe: computes each node's action key, reuses cached results, runs stages
// for the rest in parallel (oneTBB, at most `jobs` at a time), stores and publishes outputs.
// The seams (docs/architecture.md "Engine seams"): the action cache and the blob store
// (pipeline/action_cache.h, blob_store.h; the local Cache by default) and the node runner
// (pipeline/node_runner.h; a LocalRunner by default, a DryRunRunner for a dry run).
//
// Outputs of node N land in <out_dir>/N/ (out_dir is out/<recipe>/), hard-linked from the CAS
// where the file system allows (else copied); the action record of the last completed run of N
// goes to <out_dir>/.sylva/N.json for `sylva explain`. <out_dir>/.sylva/digests (DigestCache)
// remembers the stat of every published and hashed file, so a no-op build reads no content.
// A failed node stops the build (dependents and not-yet-started nodes are "skipped") unless
// keep_going, which builds everything that does not depend on a failure. Cancellation (Ctrl-C)
// starts nothing new and interrupts stages at their next check_cancelled().
#pragma once

#include <atomic>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/action.h"
#include "pipeline/action_cache.h"
#include "pipeline/blob_store.h"
#include "pipeline/cache.h"
#include "pipeline/clock.h"
#include "pipeline/digest_cache.h"
#include "pipeline/filesystem.h"
#include "pipeline/node_runner.h"
#include "pipeline/recipe.h"

namespace sylva {

enum class NodeStatus {
  kBuilt,        // the stage ran
  kCached,       // outputs came from the cache
  kFailed,       // the stage (or storing its outputs) failed
  kSkipped,      // not run: an input failed, or the build stopped after a failure
  kInterrupted,  // not run or stopped because of Ctrl-C
  kWouldBuild,   // dry run: would run
  kUpToDate,     // dry run: cached
};
const char* status_name(NodeStatus s);

struct NodeReport {
  std::string name, stage;
  NodeStatus status = NodeStatus::kSkipped;
  double seconds = 0;
  std::string key;    // action key (empty if not computed)
  std::string error;  // kFailed / kSkipped reason
  std::vector<OutputEntry> outputs;
};

class BuildObserver {
 public:
  virtual ~BuildObserver() = default;
  virtual void on_plan(std::size_t /*total*/) {}
  virtual void on_start(const std::string& /*node*/) {}
  virtual void on_finish(const NodeReport& /*report*/) {}
};

struct BuildOptions {
  int jobs = 0;  // 0 = all cores
  bool keep_going = false;
  bool dry_run = false;
  std::vector<std::string> targets;  // node names or glob patterns; empty = all nodes
  // After a build that stored new blobs, least recently used results are evicted while the
  // cache's blobs exceed this many bytes. nullopt: kDefaultCacheShare of (free disk + cache);
  // 0: never evict.
  std::optional<std::uint64_t> cache_max_bytes;
};

// The default cache limit: this share of the free space plus what the cache already holds.
inline constexpr double kDefaultCacheShare = 0.25;

struct BuildEnv {
  FileSystem& fs;
  Cache& cache;                   // the local cache: action locks, scratch directories, eviction
  std::filesystem::path out_dir;  // out/<recipe>
  const Clock& clock;
  const std::atomic<bool>* cancel = nullptr;
  BuildObserver* observer = nullptr;
  // The seams; nullptr: the local cache (`cache`) and a LocalRunner. A dry run always uses a
  // DryRunRunner.
  ActionCache* actions = nullptr;
  BlobStore* blobs = nullptr;
  NodeRunner* runner = nullptr;
};

struct BuildSummary {
  std::vector<NodeReport> nodes;  // topological order; only nodes in the target closure
  double seconds = 0;
  GcResult evicted;  // what automatic eviction removed after the build (usually nothing)
  // Nodes no longer in the recipe whose outputs this out dir held: their directories
  // (out/<recipe>/<node>/) and explain records were removed; a dry run lists them, removing nothing.
  std::vector<std::string> removed;
  // Bookkeeping that could not be written (an action result, an explain record, the digest
  // records), one message each: the build fails (exit 1) even if every node ran.
  std::vector<std::string> errors;
  std::size_t count(NodeStatus s) const;
  bool interrupted() const { return count(NodeStatus::kInterrupted) > 0; }
  bool ok() const {
    return count(NodeStatus::kFailed) == 0 && count(NodeStatus::kSkipped) == 0 && !interrupted() &&
           errors.empty();
  }
};

// Unknown targets are reported in `error` (and nothing runs).
BuildSummary run_build(const Recipe& recipe, const BuildEnv& env, const BuildOptions& options,
                       std::string* error);

// The action node `index` would run now, given the outputs of its inputs; nullopt (and
// `error`) if a declared file cannot be read. File parameters are hashed through `digests`
// (unchanged files are not read).
std::optional<ActionRecord> describe_action(const Recipe& recipe, std::size_t index,
                                            const std::vector<std::vector<OutputEntry>>& upstream,
                                            DigestCache& digests, std::string* error);

// `sylva explain`: why `node` will rebuild (or that it will not), one line per reason.
std::vector<std::string> explain_node(const Recipe& recipe, const BuildEnv& env, const std::string& node);

}  // namespace sylva
