#include "pipeline/scheduler.h"

#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <thread>

namespace sylva {

void run_in_dependency_order(const BuildGraph& graph, const std::vector<bool>& todo, int jobs,
                             const std::function<void(std::size_t)>& process) {
  const std::size_t n = graph.size();
  if (std::none_of(todo.begin(), todo.end(), [](bool b) { return b; })) return;
  if (jobs <= 0) jobs = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  // Allow -j above the core count; the arena caps concurrency.
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(jobs));
  tbb::task_arena arena(jobs);
  tbb::task_group group;
  std::vector<std::atomic<int>> pending(n);
  std::function<void(std::size_t)> launch = [&](std::size_t i) {
    group.run([&, i] {
      process(i);
      for (std::size_t d : graph.dependents(i))
        if (todo[d] && pending[d].fetch_sub(1) == 1) launch(d);
    });
  };
  arena.execute([&] {
    for (std::size_t i = 0; i < n; ++i) {
      int count = 0;
      for (std::size_t j : graph.inputs(i)) count += todo[j] ? 1 : 0;
      pending[i].store(count);
    }
    // Roots are chosen before any task starts: a fast task could otherwise bring a dependent's
    // count to zero while this loop is still looking, and that node would run twice.
    std::vector<std::size_t> roots;
    for (std::size_t i : graph.topo_order())
      if (todo[i] && pending[i].load() == 0) roots.push_back(i);
    for (std::size_t i : roots) launch(i);
    group.wait();
  });
}

}  // namespace sylva
