// How a build looks to people and machines:
//   - on a terminal, one live line: `[12/40] lod_oak_adult 3.1s ETA 20s` (redrawn in place);
//   - otherwise (CI logs), one plain line per node that ran, failed, was skipped or interrupted:
//     `[12/40] built lod_oak_adult 3.10s`. Cached nodes print nothing (as ninja prints nothing
//     for an up-to-date edge): a no-op of 10,000 nodes is one summary line, not 10,000 writes;
//     the summary line counts them and --json lists every node;
//   - failures always print `error: node 'X' (stage S): message` in full.
// The machine-readable summary (--json) is separate: summary_json().
#pragma once

#include <condition_variable>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "pipeline/clock.h"
#include "pipeline/executor.h"

namespace sylva {

class ProgressPrinter final : public BuildObserver {
 public:
  ProgressPrinter(std::FILE* out, bool live, const Clock& clock);
  ~ProgressPrinter() override;

  void on_plan(std::size_t total) override;
  void on_start(const std::string& node) override;
  void on_finish(const NodeReport& report) override;
  void stop();  // ends the live line (idempotent)

 private:
  void redraw_locked();
  void ticker();

  std::FILE* out_;
  bool live_;
  const Clock& clock_;
  std::mutex mu_;
  std::condition_variable cv_;
  std::size_t total_ = 0, done_ = 0;
  double start_ = 0, run_seconds_ = 0, last_redraw_ = -1;
  std::size_t ran_ = 0;
  std::map<std::string, double> running_;  // node -> start time
  bool stopping_ = false;
  std::thread thread_;
};

std::string summary_json(const std::string& recipe, const BuildSummary& summary);
std::string summary_line(const BuildSummary& summary);

}  // namespace sylva
