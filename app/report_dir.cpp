#include "app/report_dir.h"

#include <stdexcept>

namespace sylva {

namespace fs = std::filesystem;

namespace {
fs::path staging_path_for(const fs::path& dir) {
  const fs::path clean = dir.has_filename() ? dir : dir.parent_path();  // "a/b/" -> "a/b"
  return unique_temp_path(clean.parent_path() / ("." + clean.filename().string()));
}
}  // namespace

StagedReportDir::StagedReportDir(FileSystem& fs, fs::path report_dir)
    : fs_(fs), final_(std::move(report_dir)) {
  if (!final_.has_filename()) final_ = final_.parent_path();
  staged_ = staging_path_for(final_);
  std::string why;
  if (!fs_.make_dirs(staged_, &why))
    throw std::runtime_error(final_.string() + ": cannot create the report directory: " + why);
}

StagedReportDir::~StagedReportDir() {
  if (!committed_) fs_.remove_all(staged_);
}

void StagedReportDir::commit() {
  fs::path displaced;
  std::string why;
  if (!fs_.replace_dir(staged_, final_, &displaced, &why))
    throw std::runtime_error(final_.string() + ": cannot write the report directory: " + why);
  committed_ = true;
  if (!displaced.empty()) fs_.remove_all(displaced);
}

void StagedReportDir::remove_previous() {
  if (!committed_) fs_.remove_all(final_);
}

}  // namespace sylva
