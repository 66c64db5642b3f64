#include "libs/render/rasteriser_threads.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <thread>

namespace sylva::render {
namespace {

TEST(RasteriserThreads, TwoMoreThanTheHardwareThreads) {
  EXPECT_EQ(rasteriser_threads(2), 4u);
  EXPECT_EQ(rasteriser_threads(4), 6u);
  EXPECT_EQ(rasteriser_threads(16), 18u);
}

TEST(RasteriserThreads, OneOrUnknownHardwareThreadsLeaveLlvmpipesDefault) {
  EXPECT_EQ(rasteriser_threads(1), 0u);
  EXPECT_EQ(rasteriser_threads(0), 0u);
}

// Restores LP_NUM_THREADS as the test found it.
class LpNumThreads {
 public:
  LpNumThreads() {
    if (const char* v = std::getenv("LP_NUM_THREADS")) saved_ = v, had_ = true;
  }
  ~LpNumThreads() {
    if (had_)
      setenv("LP_NUM_THREADS", saved_.c_str(), 1);
    else
      unsetenv("LP_NUM_THREADS");
  }

 private:
  std::string saved_;
  bool had_ = false;
};

TEST(RasteriserThreads, TheEnvironmentsChoiceWins) {
  LpNumThreads restore;
  ASSERT_EQ(setenv("LP_NUM_THREADS", "7", 1), 0);
  EXPECT_FALSE(set_default_rasteriser_threads());
  EXPECT_STREQ(std::getenv("LP_NUM_THREADS"), "7");
}

TEST(RasteriserThreads, UnsetItBecomesTheRulesCount) {
  LpNumThreads restore;
  ASSERT_EQ(unsetenv("LP_NUM_THREADS"), 0);
  const unsigned n = rasteriser_threads(std::thread::hardware_concurrency());
  EXPECT_EQ(set_default_rasteriser_threads(), n != 0);
  if (n != 0) {
    ASSERT_NE(std::getenv("LP_NUM_THREADS"), nullptr);
    EXPECT_EQ(std::string(std::getenv("LP_NUM_THREADS")), std::to_string(n));
  } else {
    EXPECT_EQ(std::getenv("LP_NUM_THREADS"), nullptr);
  }
}

}  // namespace
}  // namespace sylva::render
