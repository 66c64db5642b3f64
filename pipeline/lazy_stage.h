// A stage the binary knows by its StageInfo alone, whose implementation lives in a shared
// library loaded on first run (docs/architecture.md, "Heavy libraries load lazily").
//
// `sylva stages`, recipe checking, `graph`, `explain` and a no-op build only read info(); the
// first run() asks the resolver for the real stage (which may dlopen a module) and forwards to
// it. The real stage must declare the same name and version, or run() throws std::logic_error
// (a module from another build).
#pragma once

#include <memory>
#include <string_view>

#include "pipeline/stage.h"

namespace sylva {

class StageResolver {
 public:
  virtual ~StageResolver() = default;
  // The implementation of stage `name`; throws StageError when it cannot be loaded (the node
  // fails with that message). Called from worker threads: implementations are thread-safe.
  virtual const Stage& resolve(std::string_view name) = 0;
};

// `resolver` must outlive the stage.
std::unique_ptr<Stage> make_lazy_stage(StageInfo info, StageResolver& resolver);

}  // namespace sylva
