// A command's report directory (`sylva lodcheck`, `impostorcheck`, `verify`) written whole, as a
// node's out dir is published: files go into a staging directory beside it
// (<parent>/.<name>.tmp.<pid>.<n>), and commit() swaps it into place in one rename
// (FileSystem::replace_dir), deleting the old report. Destroyed without commit() (the command
// was interrupted by Ctrl-C/SIGTERM, or failed), the staging directory is deleted: a report
// directory is always a complete report of one run, never a partial one.
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/filesystem.h"

namespace sylva {

class StagedReportDir {
 public:
  // Creates the staging directory (and the report's parent) through `fs`, which must outlive
  // this object (the command's CommandContext::fs). Throws std::runtime_error with the reason if
  // it cannot.
  StagedReportDir(FileSystem& fs, std::filesystem::path report_dir);
  ~StagedReportDir();
  StagedReportDir(const StagedReportDir&) = delete;
  StagedReportDir& operator=(const StagedReportDir&) = delete;

  // Where the command writes its files until commit().
  const std::filesystem::path& path() const { return staged_; }
  // Where they are after commit().
  const std::filesystem::path& final_path() const { return final_; }
  // Moves the staged report into place. Throws std::runtime_error with the reason if it cannot.
  void commit();
  // Deletes the previous report too (a failed run must not leave an older run's report under
  // the name, as if it were this run's).
  void remove_previous();

 private:
  FileSystem& fs_;
  std::filesystem::path final_, staged_;
  bool committed_ = false;
};

}  // namespace sylva
