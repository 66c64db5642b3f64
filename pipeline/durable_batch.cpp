#include "pipeline/durable_batch.h"

namespace sylva {

DurableBatch::DurableBatch(ActionCache& actions, BlobStore& blobs) : actions_(actions), blobs_(blobs) {}

DurableBatch::~DurableBatch() { finish(); }

void DurableBatch::commit(std::string key, ActionResult result, std::unique_ptr<FileLock> lock) {
  {
    std::lock_guard l(mu_);
    queue_.push_back({std::move(key), std::move(result), std::move(lock)});
    // Started by the first result: a no-op build has no thread and syncs nothing.
    if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
  }
  cv_.notify_one();
}

std::vector<std::string> DurableBatch::store(std::vector<Item>& batch) {
  std::vector<std::string> errors;
  std::string why;
  std::vector<Digest> blobs;
  for (const Item& item : batch)
    for (const auto& o : item.result.outputs) blobs.push_back(o.digest);
  // Every blob these results name was moved into the store before it was queued.
  if (!blobs_.make_durable(blobs, &why)) {
    errors.push_back("cannot make the cache's blobs durable (" + why + "); " + std::to_string(batch.size()) +
                     " action result(s) not stored");
    return errors;
  }
  // Not yet durable: finish() makes every result of the build durable at once. Until then a
  // power loss can only lose a result (its action runs again), never its blobs.
  for (const Item& item : batch) {
    if (actions_.store(item.key, item.result, /*durable=*/false, &why))
      stored_.push_back(item.key);
    else
      errors.push_back("cannot write action result " + why);
  }
  return errors;
}

void DurableBatch::run() {
  std::unique_lock l(mu_);
  for (;;) {
    cv_.wait(l, [&] { return !queue_.empty() || stopping_; });
    if (queue_.empty()) break;
    std::vector<Item> batch;
    batch.swap(queue_);
    busy_ = true;
    l.unlock();
    std::vector<std::string> errors = store(batch);
    batch.clear();  // releases the action locks
    l.lock();
    errors_.insert(errors_.end(), errors.begin(), errors.end());
    busy_ = false;
    idle_.notify_all();
  }
}

bool DurableBatch::finish(std::vector<std::string>* errors) {
  std::unique_lock l(mu_);
  if (!finished_) {
    finished_ = true;
    stopping_ = true;
    const bool started = thread_.joinable();
    cv_.notify_one();
    l.unlock();
    if (started) thread_.join();
    l.lock();
    std::string why;
    if (!actions_.make_durable(stored_, &why))
      errors_.push_back("cannot make the cache's action results durable (" + why + ")");
  }
  if (errors) *errors = errors_;
  return errors_.empty();
}

}  // namespace sylva
