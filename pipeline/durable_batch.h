// Group commit of action results: the durability of a cold build without an fsync per file.
//
// A stored action result is a promise that its blobs are on disk. Making each blob durable
// before its result is written cost two fsyncs per node (blob, then entry and directory): a
// 10,000-node cold build spent minutes waiting on the disk. Instead stages' outputs are renamed
// into the CAS without an fsync, and their results are queued here; one committer thread takes
// everything queued so far, calls syncfs(2) once (every blob and rename of the batch is then
// durable), writes the batch's results, and releases their action locks; nodes keep running
// meanwhile, and a batch grows while the previous sync runs (group commit). finish() waits for
// the queue to drain and syncs once more, so when a build returns its results are durable too.
//
// Crash safety is unchanged: a result is never written before the blobs it names are durable;
// a kill -9 or power loss before that loses only unwritten results (those actions run again),
// never leaves a result naming a missing or partial blob. The action lock is held until the
// result is written, so a concurrent build waiting for it finds the result (no double run).
#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/cache.h"
#include "pipeline/filesystem.h"

namespace sylva {

class DurableBatch {
 public:
  DurableBatch(FileSystem& fs, Cache& cache);
  ~DurableBatch();  // finish()
  DurableBatch(const DurableBatch&) = delete;
  DurableBatch& operator=(const DurableBatch&) = delete;

  // Queues the result of action `key`; `lock` (the action's lock, may be null) is released
  // once the result is written or has failed to be.
  void commit(std::string key, ActionResult result, std::unique_ptr<FileLock> lock);
  // Waits until every queued result is written and durable. False (and every problem, one per
  // line, in `errors`) if a sync or a write failed: those results are not stored.
  bool finish(std::vector<std::string>* errors = nullptr);

 private:
  struct Item {
    std::string key;
    ActionResult result;
    std::unique_ptr<FileLock> lock;
  };
  void run();

  FileSystem& fs_;
  Cache& cache_;
  std::mutex mu_;
  std::condition_variable cv_, idle_;  // idle_: a batch finished
  std::vector<Item> queue_;
  bool busy_ = false, stopping_ = false, finished_ = false;
  std::vector<std::string> errors_;
  std::thread thread_;
};

}  // namespace sylva
