// A Clock for tests: time stands still at `now` until the test moves it.
#pragma once

#include <atomic>

#include "pipeline/clock.h"

namespace sylva::test {

class FakeClock final : public Clock {
 public:
  std::atomic<double> now{1000.0};  // seconds; monotonic as long as tests only add to it
  double now_seconds() const override { return now.load(); }
};

}  // namespace sylva::test
