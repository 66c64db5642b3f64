// Group commit of action results: the durability of a build at the cost of what it wrote.
//
// A stored action result is a promise that its blobs are on disk. Stages' outputs are moved into
// the blob store without waiting for the disk, and their results are queued here; one committer
// thread takes everything queued so far, makes that batch's blobs durable (BlobStore::
// make_durable: for the local cache an fsync of each blob and of each directory holding one, or
// one syncfs(2) for a large batch), writes the batch's results and releases their action locks.
// Nodes keep running meanwhile, and a batch grows while the previous one is being synced (group
// commit). finish() waits for the queue to drain and makes every result written durable
// (ActionCache::make_durable), so when a build returns its results are durable. A small build
// syncs only its own files: a one-node build does not wait for every other process's dirty pages.
//
// Crash safety: a result is never written before the blobs it names are durable; a kill -9 or
// power loss before that loses only unwritten results (those actions run again), never leaves
// a result naming a missing or partial blob. The action lock is held until the result is
// written, so a concurrent build waiting for it finds the result (no double run).
#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "pipeline/action_cache.h"
#include "pipeline/blob_store.h"
#include "pipeline/filesystem.h"

namespace sylva {

class DurableBatch {
 public:
  DurableBatch(ActionCache& actions, BlobStore& blobs);
  ~DurableBatch();  // finish()
  DurableBatch(const DurableBatch&) = delete;
  DurableBatch& operator=(const DurableBatch&) = delete;

  // Queues the result of action `key`, whose blobs were stored without `durable`; `lock` (the
  // action's lock, may be null) is released once the result is written or has failed to be.
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
  // Stores one batch durably; the problems, one line each.
  std::vector<std::string> store(std::vector<Item>& batch);

  ActionCache& actions_;
  BlobStore& blobs_;
  std::mutex mu_;
  std::condition_variable cv_, idle_;  // idle_: a batch finished
  std::vector<Item> queue_;
  bool busy_ = false, stopping_ = false, finished_ = false;
  std::vector<std::string> errors_;
  std::vector<std::string> stored_;  // keys of the results written (by the committer thread)
  std::thread thread_;
};

}  // namespace sylva
