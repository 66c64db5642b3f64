#include "pipeline/lazy_stage.h"

#include <stdexcept>
#include <string>

namespace sylva {

namespace {

class LazyStage final : public Stage {
 public:
  LazyStage(StageInfo info, StageResolver& resolver) : info_(std::move(info)), resolver_(resolver) {}

  const StageInfo& info() const override { return info_; }

  void run(StageContext& ctx) const override {
    const Stage& real = resolver_.resolve(info_.name);
    // The version is part of the action key: a module whose stage differs from what the binary
    // declared would store results under the wrong key.
    if (real.info().name != info_.name || real.info().version != info_.version)
      throw std::logic_error("stage '" + info_.name + "' v" + std::to_string(info_.version) +
                             " resolved to '" + real.info().name + "' v" +
                             std::to_string(real.info().version) + " (the module comes from another build)");
    real.run(ctx);
  }

 private:
  StageInfo info_;
  StageResolver& resolver_;
};

}  // namespace

std::unique_ptr<Stage> make_lazy_stage(StageInfo info, StageResolver& resolver) {
  return std::make_unique<LazyStage>(std::move(info), resolver);
}

}  // namespace sylva
