#include "app/progress.h"

#include <nlohmann/json.hpp>

namespace sylva {

ProgressPrinter::ProgressPrinter(std::FILE* out, bool live, const Clock& clock)
    : out_(out), live_(live), clock_(clock), start_(clock.now_seconds()) {
  if (live_) thread_ = std::thread([this] { ticker(); });
}

ProgressPrinter::~ProgressPrinter() { stop(); }

void ProgressPrinter::stop() {
  {
    std::lock_guard lock(mu_);
    if (stopping_) return;
    stopping_ = true;
    if (live_) std::fprintf(out_, "\r\x1b[K");
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
  std::fflush(out_);
}

void ProgressPrinter::on_plan(std::size_t total) {
  std::lock_guard lock(mu_);
  total_ = total;
}

void ProgressPrinter::on_start(const std::string& node) {
  std::lock_guard lock(mu_);
  running_[node] = clock_.now_seconds();
  if (live_) redraw_locked();
}

void ProgressPrinter::on_finish(const NodeReport& r) {
  std::lock_guard lock(mu_);
  ++done_;
  if (auto it = running_.find(r.name); it != running_.end()) running_.erase(it);
  if (r.status == NodeStatus::kBuilt) {
    ++ran_;
    run_seconds_ += r.seconds;
  }
  const bool quiet = r.status == NodeStatus::kCached || r.status == NodeStatus::kUpToDate;
  if (!live_ && quiet) return;
  // On a terminal a cached node only moves the counter: redraw at most ten times a second.
  if (live_ && quiet && clock_.now_seconds() - last_redraw_ < 0.1) return;
  if (live_) std::fprintf(out_, "\r\x1b[K");
  if (r.status == NodeStatus::kFailed) {
    std::fprintf(out_, "error: node '%s' (stage %s): %s\n", r.name.c_str(), r.stage.c_str(), r.error.c_str());
  } else if (!live_) {
    std::fprintf(out_, "[%zu/%zu] %s %s %.2fs\n", done_, total_, status_name(r.status), r.name.c_str(),
                 r.seconds);
  }
  if (live_) redraw_locked();
  std::fflush(out_);
}

void ProgressPrinter::redraw_locked() {
  if (stopping_) return;
  const double now = clock_.now_seconds();
  std::string line = "[" + std::to_string(done_) + "/" + std::to_string(total_) + "]";
  if (!running_.empty()) {
    // Show the longest-running node: it is what the user is waiting for.
    auto oldest = running_.begin();
    for (auto it = running_.begin(); it != running_.end(); ++it)
      if (it->second < oldest->second) oldest = it;
    char buf[64];
    std::snprintf(buf, sizeof buf, " %.1fs", now - oldest->second);
    line += " " + oldest->first + buf;
    if (running_.size() > 1) line += " (+" + std::to_string(running_.size() - 1) + " running)";
  }
  if (ran_ > 0 && total_ > done_) {
    // Average time of nodes that actually ran, times what is left, shared by the workers busy now.
    const double avg = run_seconds_ / static_cast<double>(ran_);
    const double eta =
        avg * static_cast<double>(total_ - done_) / std::max<double>(1, static_cast<double>(running_.size()));
    char buf[32];
    std::snprintf(buf, sizeof buf, " ETA %.0fs", eta);
    line += buf;
  }
  std::fprintf(out_, "\r\x1b[K%s", line.c_str());
  std::fflush(out_);
  last_redraw_ = now;
}

void ProgressPrinter::ticker() {
  std::unique_lock lock(mu_);
  while (!stopping_) {
    cv_.wait_for(lock, std::chrono::milliseconds(200));
    if (!stopping_ && !running_.empty()) redraw_locked();
  }
}

std::string summary_json(const std::string& recipe, const BuildSummary& s) {
  nlohmann::ordered_json j;
  j["recipe"] = recipe;
  j["ok"] = s.ok();
  j["built"] = s.count(NodeStatus::kBuilt);
  j["cached"] = s.count(NodeStatus::kCached);
  j["failed"] = s.count(NodeStatus::kFailed);
  j["skipped"] = s.count(NodeStatus::kSkipped);
  j["interrupted"] = s.count(NodeStatus::kInterrupted);
  j["would_build"] = s.count(NodeStatus::kWouldBuild);
  j["up_to_date"] = s.count(NodeStatus::kUpToDate);
  j["seconds"] = s.seconds;
  j["removed"] = s.removed;
  j["nodes"] = nlohmann::ordered_json::array();
  for (const auto& r : s.nodes) {
    nlohmann::ordered_json n;
    n["name"] = r.name;
    n["stage"] = r.stage;
    n["status"] = status_name(r.status);
    n["seconds"] = r.seconds;
    n["key"] = r.key;
    if (!r.error.empty()) n["error"] = r.error;
    n["outputs"] = nlohmann::ordered_json::array();
    for (const auto& o : r.outputs)
      n["outputs"].push_back({{"name", o.name}, {"sha256", o.digest.hash}, {"size", o.digest.size}});
    j["nodes"].push_back(n);
  }
  return j.dump(2) + "\n";
}

std::string summary_line(const BuildSummary& s) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%zu nodes: %zu built, %zu cached, %zu failed, %zu skipped in %.2fs",
                s.nodes.size(), s.count(NodeStatus::kBuilt), s.count(NodeStatus::kCached),
                s.count(NodeStatus::kFailed), s.count(NodeStatus::kSkipped), s.seconds);
  std::string out = buf;
  if (s.interrupted()) out += " (interrupted)";
  return out;
}

}  // namespace sylva
