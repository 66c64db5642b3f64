#include "pipeline/local_runner.h"

#include <oneapi/tbb/task_arena.h>

#include "pipeline/node_context.h"

namespace sylva {

namespace fs = std::filesystem;

NodeRun LocalRunner::run(const NodeJob& job) {
  const fs::path scratch = scratch_.make_scratch_dir();
  // Whatever happens, the scratch directory goes: a failed or interrupted stage leaves nothing.
  struct Cleanup {
    FileSystem& fs;
    const fs::path& dir;
    ~Cleanup() { fs.remove_all(dir); }
  } cleanup{fs_, scratch};
  const fs::path out = scratch / "out";
  const fs::path work = scratch / "work";
  fs_.make_dirs(out);
  fs_.make_dirs(work);
  NodeContext ctx(fs_, job.node, job.inputs, work, out, cancel_);
  // Isolated: while this thread waits inside the stage's own parallel loops it runs only their
  // tasks, never another node (which could wait for the action lock held by the caller).
  tbb::this_task_arena::isolate([&] { job.node.stage->run(ctx); });
  ctx.check_cancelled();
  for (const auto& name : fs_.list(out))
    if (!ctx.declared().count(name)) throw StageError("stage wrote undeclared output file '" + name + "'");
  if (ctx.declared().empty()) throw StageError("stage wrote no output");
  NodeRun run;
  run.executed = true;
  for (const auto& name : ctx.declared()) {
    auto st = fs_.stat(out / name);
    if (!st || st->is_dir || st->is_other)
      throw StageError("stage declared output '" + name + "' but did not write it");
    auto known = ctx.known_digest(name);
    if (known && known->size != st->size) known.reset();  // rewritten behind the context's back
    std::string why;
    auto d = blobs_.put_file(out / name, nullptr, /*durable=*/false, &why, known);
    if (!d) {
      ctx.check_cancelled();
      throw StageError("cannot store output '" + name + "' in the cache at " + scratch_.root().string() +
                       ": " + why);
    }
    run.result.outputs.push_back({name, *d});
  }
  return run;
}

}  // namespace sylva
