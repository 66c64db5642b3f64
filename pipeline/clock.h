// Time, behind an interface so tests can fake it (timings appear only in logs and --json).
#pragma once

#include <chrono>

namespace sylva {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual double now_seconds() const = 0;  // monotonic
};

class SteadyClock final : public Clock {
 public:
  double now_seconds() const override {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  }
};

}  // namespace sylva
