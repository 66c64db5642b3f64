// The judgement of lodcheck, impostorcheck and the forest check in one place (judge.h), so the
// three checks cannot drift apart: the same statistics (libs/image/coverage.h), the same strict
// bounds, the same sentences in their reports.
#include "libs/check/judge.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace sylva::check {

std::string coverage_failure(const image::FootprintStats& s, const CoverageThresholds& t,
                             std::string_view subject) {
  const std::string noun(subject);
  char buf[256];
  if (s.footprint_pixels == 0 && t.empty_fails) return "neither render covers a pixel";
  if (s.failing_fraction > t.max_failing_fraction) {
    std::snprintf(buf, sizeof buf,
                  "coverage of %.2f%% of the %s's %zu pixels changed by more than %.3g (allowed %.2f%%)",
                  100 * s.failing_fraction, noun.c_str(), s.footprint_pixels, t.pixel_threshold,
                  100 * t.max_failing_fraction);
    return buf;
  }
  if (s.coverage_mean_error > t.max_coverage_error) {
    std::snprintf(buf, sizeof buf, "mean coverage change over the %s's %zu pixels is %.4f (allowed %.4f)",
                  noun.c_str(), s.footprint_pixels, s.coverage_mean_error, t.max_coverage_error);
    return buf;
  }
  return {};
}

ViewJudgement judge_coverage(const image::Image& reference, const image::Image& test,
                             const CoverageThresholds& thresholds, std::string_view subject) {
  ViewJudgement j;
  j.stats = image::footprint_stats(reference, test, thresholds.pixel_threshold);
  j.failure = coverage_failure(j.stats, thresholds, subject);
  return j;
}

double colour_bound(double max_colour_error, double ratio, double baseline) {
  return baseline < 0 ? max_colour_error : std::max(max_colour_error, ratio * baseline);
}

std::string colour_failure(double shade_mean_error, double bound) {
  if (!(shade_mean_error > bound)) return {};
  char buf[160];
  std::snprintf(buf, sizeof buf, "mean colour difference where both cover the tree is %.4f (allowed %.4f)",
                shade_mean_error, bound);
  return buf;
}

std::string mean_colour_failure(double mean, double baseline_mean, double tolerance,
                                std::string_view baseline_label) {
  if (!(mean > baseline_mean + tolerance)) return {};
  const std::string label(baseline_label);
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "mean colour difference over the views is %.4f, more than the %s's %.4f + %.3g", mean,
                label.c_str(), baseline_mean, tolerance);
  return buf;
}

}  // namespace sylva::check
