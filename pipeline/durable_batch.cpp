#include "pipeline/durable_batch.h"

namespace sylva {

DurableBatch::DurableBatch(FileSystem& fs, Cache& cache) : fs_(fs), cache_(cache) {}

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

void DurableBatch::run() {
  std::unique_lock l(mu_);
  for (;;) {
    cv_.wait(l, [&] { return !queue_.empty() || stopping_; });
    if (queue_.empty()) break;
    std::vector<Item> batch;
    batch.swap(queue_);
    busy_ = true;
    l.unlock();
    std::vector<std::string> errors;
    std::string why;
    // Every blob these results name was renamed into the CAS before it was queued.
    if (!fs_.sync_fs(cache_.root(), &why)) {
      errors.push_back("cannot make the cache at " + cache_.root().string() + " durable (" + why + "); " +
                       std::to_string(batch.size()) + " action result(s) not stored");
    } else {
      for (Item& item : batch) {
        if (!cache_.store_action(item.key, item.result, /*durable=*/false, &why))
          errors.push_back("cannot write action result " + cache_.action_path(item.key).string() + ": " +
                           why);
      }
    }
    batch.clear();  // releases the action locks
    l.lock();
    errors_.insert(errors_.end(), errors.begin(), errors.end());
    busy_ = false;
    idle_.notify_all();
  }
}

bool DurableBatch::finish(std::vector<std::string>* errors) {
  {
    std::unique_lock l(mu_);
    if (!finished_) {
      finished_ = true;
      stopping_ = true;
      const bool started = thread_.joinable();
      cv_.notify_one();
      l.unlock();
      if (started) thread_.join();
      l.lock();
      // The results written by the last batch (and their directory entries) become durable.
      std::string why;
      if (started && !fs_.sync_fs(cache_.root(), &why))
        errors_.push_back("cannot make the cache at " + cache_.root().string() + " durable (" + why + ")");
    }
    if (errors) *errors = errors_;
    return errors_.empty();
  }
}

}  // namespace sylva
