// The seam between deciding what to build and building it (ninja's CommandRunner): the build
// loop hands every node whose result is neither in its out dir nor in the cache to a NodeRunner.
//   LocalRunner   (pipeline/local_runner.h) runs the stage in this process, in a scratch
//                 directory, and stores its outputs in the blob store;
//   DryRunRunner  (below) runs nothing: `sylva build --dry-run` reports what would build, and the
//                 build loop, seeing executes() false, writes nothing either;
// and a runner that submits the action to a cluster, whose worker stores the result in a shared
// cache, fits the same interface. Tests use their own runners (tests/engine/build_seams_test.cpp).
#pragma once

#include <string>
#include <vector>

#include "pipeline/action_cache.h"
#include "pipeline/recipe.h"
#include "pipeline/stage.h"

namespace sylva {

// One action to run: the node (its stage and parameters), its key, and its inputs' files as the
// stage will see them.
struct NodeJob {
  const NodeDecl& node;
  std::string key;
  std::vector<InputArtifact> inputs;
};

struct NodeRun {
  bool executed = false;  // false: nothing ran (a dry run): the node would build
  ActionResult result;    // when executed: the outputs, every one stored in the blob store
};

class NodeRunner {
 public:
  virtual ~NodeRunner() = default;
  // Runs job's action and stores every output in the blob store (not yet durably: the build
  // loop's DurableBatch does that before the result is stored). Throws StageError (bad input, a
  // stage that broke its contract, an output that could not be stored: the node fails with the
  // message), Cancelled (Ctrl-C: the node is interrupted) or anything else (a bug: the node
  // fails with what it says). Called from several threads at once.
  virtual NodeRun run(const NodeJob& job) = 0;
  // False for a runner that executes nothing (a dry run): the build then publishes, withdraws
  // and records nothing, and takes no lock.
  virtual bool executes() const { return true; }
};

class DryRunRunner final : public NodeRunner {
 public:
  NodeRun run(const NodeJob&) override { return {}; }
  bool executes() const override { return false; }
};

}  // namespace sylva
