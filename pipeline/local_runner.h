// Runs a node's stage in this process (NodeRunner): in a fresh scratch directory of the local
// cache, through a NodeContext on the engine's FileSystem, inside its own oneTBB isolation; then
// checks that the stage wrote exactly what it declared and moves each output into the blob store.
#pragma once

#include <atomic>

#include "pipeline/blob_store.h"
#include "pipeline/cache.h"
#include "pipeline/filesystem.h"
#include "pipeline/node_runner.h"

namespace sylva {

class LocalRunner final : public NodeRunner {
 public:
  // `scratch` provides the scratch directories (on the same file system as `blobs`' files, so
  // storing an output is a rename); `cancel` (may be null) is raised by Ctrl-C.
  LocalRunner(FileSystem& fs, Cache& scratch, BlobStore& blobs, const std::atomic<bool>* cancel)
      : fs_(fs), scratch_(scratch), blobs_(blobs), cancel_(cancel) {}
  NodeRun run(const NodeJob& job) override;

 private:
  FileSystem& fs_;
  Cache& scratch_;
  BlobStore& blobs_;
  const std::atomic<bool>* cancel_;
};

}  // namespace sylva
