// How many rasteriser threads sylva asks Mesa's llvmpipe for (docs/renderer.md "Rasteriser
// threads"). llvmpipe bins every draw on the calling thread and shades the bins on its own thread
// pool, one thread per hardware thread unless LP_NUM_THREADS says otherwise; it reads the variable
// once, when the first context's screen is created. The binning thread shares the cores with the
// pool; two pool threads more than the hardware threads were measured fastest on 2 cores (forest
// views: the edge frame of a four-frame walk through configs/forest_celba.yaml, further frames
// 4.24-5.34 s with 3 threads, 4.12-4.38 s with 4; docs/renderer.md "Rasteriser threads") with the
// same pixels (llvmpipe gives each tile to one thread, in bin order, whatever the count).
//
// Header-only, so that a program's main() sets it before anything links or starts the renderer.
#pragma once

#include <cstdlib>
#include <string>
#include <thread>

namespace sylva::render {

// The rasteriser threads for a machine with `hardware_threads` (std::thread::hardware_concurrency):
// two more; 0 (leave llvmpipe's default) when the count is unknown (0) or 1 (llvmpipe then
// rasterises on the calling thread).
inline unsigned rasteriser_threads(unsigned hardware_threads) {
  return hardware_threads < 2 ? 0 : hardware_threads + 2;
}

// Sets LP_NUM_THREADS to rasteriser_threads(hardware threads) unless the environment already sets
// it (a user's or CI's choice wins) or the rule leaves the default. Call first in main(), before
// any other thread exists (setenv is not safe against a concurrent getenv) and before any renderer
// is created. Returns whether it set the variable.
inline bool set_default_rasteriser_threads() {
  if (std::getenv("LP_NUM_THREADS") != nullptr) return false;
  const unsigned n = rasteriser_threads(std::thread::hardware_concurrency());
  if (n == 0) return false;
  return setenv("LP_NUM_THREADS", std::to_string(n).c_str(), 0) == 0;
}

}  // namespace sylva::render
