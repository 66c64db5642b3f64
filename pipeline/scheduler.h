// Runs a build's nodes in dependency order on oneTBB: each node as soon as all of its inputs that
// are to run have finished, at most `jobs` at a time. Whoever calls it writes each node's result
// into that node's own slot, so the order tasks finish in never shows in the result.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "pipeline/graph.h"

namespace sylva {

// Runs process(i) once for every node i with todo[i], after process(j) returned for each of its
// inputs j with todo[j] (inputs without todo count as done). `jobs` may exceed the core count
// (stages may wait on I/O or on a cluster); 0 = all cores. process must not throw: an exception
// escaping into oneTBB terminates the process. Returns when every node has been processed.
void run_in_dependency_order(const BuildGraph& graph, const std::vector<bool>& todo, int jobs,
                             const std::function<void(std::size_t)>& process);

}  // namespace sylva
