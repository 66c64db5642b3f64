// One scene renderer per process (shared_renderer.h).
#include "libs/render/shared_renderer.h"

#include <mutex>

namespace sylva::render {

Renderer& shared_renderer() {
  static std::mutex mu;
  static Renderer* renderer = nullptr;
  std::lock_guard<std::mutex> lock(mu);
  if (!renderer) renderer = Renderer::create_headless().release();
  return *renderer;
}

}  // namespace sylva::render
