// The three report files of a verification run, all deterministic (no times, no absolute paths:
// the same Report always gives the same bytes). Formats: docs/stages/verify.md.
//   report.json  machine-readable: thresholds, device, one object per case with every number
//   junit.xml    JUnit XML (one <testsuite> per asset, one <testcase> per view; failures and
//                missing references are <failure>, unreadable assets are <error>)
//   report.html  one self-contained page: summary, then reference / new / diff side by side with
//                the numbers for each case; every image is embedded as a base64 data URI
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

#include "stages/verify/verify_core.h"

namespace sylva::verify {

std::string report_json(const Report& report);
std::string junit_xml(const Report& report);
std::string report_html(const Report& report);

// One line for logs and StageError: "2 of 12 views failed verification: mesh_oak/front: 2.40%
// of pixels differ ...; mesh_birch/top: no reference image ..." (at most `max_listed` cases,
// then "and N more"). "all N views passed" when the report passed.
std::string summary_line(const Report& report, std::size_t max_listed = 5);

// Writes report.json, junit.xml and report.html through `output_path` (as RunEnv::output_path).
// Throws VerifyError when a file cannot be written.
void write_reports(const Report& report,
                   const std::function<std::filesystem::path(const std::string&)>& output_path);

// Base64 (RFC 4648, with padding) of `bytes`; OpenSSL's encoder.
std::string base64(const std::string& bytes);

}  // namespace sylva::verify
