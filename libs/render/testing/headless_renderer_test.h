// Test helper: the gtest fixture of tests that draw with the real headless renderer (EGL +
// OpenGL, Mesa llvmpipe): one renderer per test suite. Header-only; for tests only.
//
// Such tests skip only on a machine without any EGL vendor; with Mesa's EGL installed (every
// sylva build machine and CI), or SYLVA_REQUIRE_GL=1, failing to create a renderer fails them.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "libs/render/renderer.h"

namespace sylva::render::testing {

// Ends the running test where no headless GL could be made (`why`: the RenderUnavailableError's
// message): a failure where one is expected (see above), a skip elsewhere. Call from SetUp().
inline void fail_or_skip_without_gl(const std::string& why) {
  const char* require = std::getenv("SYLVA_REQUIRE_GL");
  std::error_code ec;
  if ((require && std::string(require) == "1") ||
      std::filesystem::exists("/usr/share/glvnd/egl_vendor.d/50_mesa.json", ec))
    FAIL() << why;
  GTEST_SKIP() << why;
}

// Creates `renderer_` once per test suite (`unavailable_` says why when it cannot) and ends each
// test without one as fail_or_skip_without_gl() says.
class HeadlessRendererTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    try {
      renderer_ = Renderer::create_headless();
    } catch (const RenderUnavailableError& e) {
      unavailable_ = e.what();
    }
  }
  static void TearDownTestSuite() { renderer_.reset(); }
  void SetUp() override {
    if (!renderer_) fail_or_skip_without_gl(unavailable_);
  }

  static inline std::unique_ptr<Renderer> renderer_;
  static inline std::string unavailable_;
};

}  // namespace sylva::render::testing
