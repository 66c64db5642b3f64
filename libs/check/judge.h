// The verdict on one view of a visual check: a render of the subject under test (a LOD level, an
// impostor, a forest's LOD-selected view) against a render of its reference (the full detail)
// from the same camera. Used by `sylva lodcheck` (stages/lod/check, stages/forest/check) and
// `sylva impostorcheck` (stages/impostor/check); docs/stages/lod.md justifies the thresholds.
//
// Contract of the inputs: two RGBA8 images of equal size rendered over a transparent background,
// so a pixel's alpha is the fraction of it the subject covers (libs/image/coverage.h). Images of
// different sizes are the caller's error to report (every statistic is then 0).
//
// Coverage (judged): a level whose geometry is within delta pixels of the reference moves an
// edge by at most delta, which changes a pixel's coverage by at most delta. A footprint pixel
// (covered in either image) fails when its coverage changes by more than `pixel_threshold`
// (delta); a view fails when more than `max_failing_fraction` of the footprint fails, or else
// when the mean coverage change over the footprint exceeds `max_coverage_error`. Both bounds are
// strict: a value equal to its bound passes.
//
// Colour (judged only when the caller gives a bound): shade_mean_error, the mean per-channel RGB
// difference weighted by the coverage both images share (coverage.h), against a bound; with a
// baseline (the model the subject replaces, measured from the same cameras) the bound grows to
// ratio x the baseline's own difference in that view, and the views' mean may exceed the
// baseline's mean by at most a tolerance.
//
// Pure functions: no rendering, no I/O. Failure sentences are the reports' text, byte for byte.
#pragma once

#include <string>
#include <string_view>

#include "libs/image/coverage.h"
#include "libs/image/image.h"

namespace sylva::check {

struct CoverageThresholds {
  double pixel_threshold = 0.5;        // coverage units (0..1): delta's 0.5 px
  double max_failing_fraction = 0.01;  // of the footprint (0..1)
  double max_coverage_error = 0.15;    // mean |coverage change| over the footprint (0..1)
  // Whether a view whose footprint is empty (neither image covers a pixel) fails. lodcheck lets it
  // pass (nothing is drawn wrongly); impostorcheck fails it (its distance search stops there).
  bool empty_fails = false;
};

// One view's numbers and verdict.
struct ViewJudgement {
  image::FootprintStats stats;
  std::string failure;  // empty when passed, else one sentence
  bool passed() const { return failure.empty(); }
};

// Why `stats` fails the coverage thresholds, or "" when they pass. `subject` is the noun of the
// sentence: "coverage of 2.00% of the tree's 500 pixels changed by more than 0.5 (allowed
// 1.00%)", "mean coverage change over the forest's 500 pixels is 0.2000 (allowed 0.1500)",
// "neither render covers a pixel" (empty footprint, when empty_fails).
std::string coverage_failure(const image::FootprintStats& stats, const CoverageThresholds& thresholds,
                             std::string_view subject);

// footprint_stats of the pair and the coverage verdict (above).
ViewJudgement judge_coverage(const image::Image& reference, const image::Image& test,
                             const CoverageThresholds& thresholds, std::string_view subject);

// The colour bound of one view: max_colour_error without a baseline (baseline < 0), else
// max(max_colour_error, ratio x baseline).
double colour_bound(double max_colour_error, double ratio, double baseline);

// Why a view's shade_mean_error fails `bound` ("mean colour difference where both cover the tree
// is 0.1200 (allowed 0.1000)"), or "" when shade <= bound.
std::string colour_failure(double shade_mean_error, double bound);

// Why the views' mean colour difference fails against the baseline's mean ("mean colour
// difference over the views is 0.0800, more than the lod5.glb's 0.0500 + 0.02"), or "" when
// mean <= baseline_mean + tolerance.
std::string mean_colour_failure(double mean, double baseline_mean, double tolerance,
                                std::string_view baseline_label);

}  // namespace sylva::check
