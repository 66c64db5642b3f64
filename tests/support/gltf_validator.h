// The Khronos glTF-Validator from tests: every glTF/GLB file a test writes goes through it.
//
// Runs `node tools/validate_gltf.mjs FILE...` (the script and the npm package gltf-validator
// that tools/setup.sh installs into out/npm) and parses its summary lines. The script is found
// from $SYLVA_SOURCE_DIR, else from the working directory or one of its parents (tests run from
// the repository root).
//
// When node, the script or the package is missing the result is `skipped` (with the reason), so
// a test can GTEST_SKIP() on machines without the tools. CI and the project machines must really
// validate: with the environment variable SYLVA_REQUIRE_GLTF_VALIDATOR=1 a missing validator is
// reported as a failure instead (skipped stays false, `tool_error` is set).
//
// Typical use:
//   const auto v = sylva::test::validate_gltf(path);
//   if (v.skipped) GTEST_SKIP() << v.skip_reason;
//   EXPECT_TRUE(v.ok()) << v.report;
// or simply SYLVA_EXPECT_VALID_GLTF(path), which does the same and skips when needed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace sylva::test {

struct ValidationResult {
  std::filesystem::path file;
  bool skipped = false;  // the validator could not run here (see skip_reason)
  std::string skip_reason;
  std::string tool_error;  // the validator ran but could not validate the file (unreadable,
                           // not glTF), or is required and missing; counts as a failure
  int errors = 0;
  int warnings = 0;
  std::vector<std::string> messages;  // "error CODE /pointer: text" and "warning ..." lines
  std::string report;                 // the script's complete output for this file

  // Validated with zero errors (warnings are allowed).
  bool ok() const { return !skipped && tool_error.empty() && errors == 0; }
};

// Validates one file.
ValidationResult validate_gltf(const std::filesystem::path& file);

// Validates several files with one node process (faster); results in the order given.
std::vector<ValidationResult> validate_gltf(const std::vector<std::filesystem::path>& files);

}  // namespace sylva::test

// Validates `path` with zero errors; skips the test (GTEST_SKIP) when the validator cannot run.
#define SYLVA_EXPECT_VALID_GLTF(path)                                                    \
  do {                                                                                   \
    const ::sylva::test::ValidationResult sylva_v_ = ::sylva::test::validate_gltf(path); \
    if (sylva_v_.skipped) GTEST_SKIP() << sylva_v_.skip_reason;                          \
    EXPECT_TRUE(sylva_v_.ok()) << sylva_v_.tool_error << "\n" << sylva_v_.report;        \
  } while (0)
