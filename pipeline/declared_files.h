// The files a node declared (StageContext::files()), read through the engine's FileSystem: its
// inputs' files, and the files and directories its file parameters name. A path outside them is
// a stage reading what is not in its action key: read() throws std::logic_error (a bug in the
// stage, reported as one), exists() says false.
#pragma once

#include <filesystem>
#include <set>
#include <string>

#include "libs/fileio/file_source.h"
#include "pipeline/filesystem.h"

namespace sylva {

class DeclaredFiles final : public fileio::FileSource {
 public:
  explicit DeclaredFiles(FileSystem& fs) : fs_(fs) {}
  void allow_file(const std::filesystem::path& p) { files_.insert(p.lexically_normal()); }
  void allow_dir(const std::filesystem::path& p) { dirs_.insert(p.lexically_normal()); }

  std::string read(const std::filesystem::path& path) const override;
  bool exists(const std::filesystem::path& path) const override;

 private:
  bool declared(const std::filesystem::path& normal) const;

  FileSystem& fs_;
  std::set<std::filesystem::path> files_, dirs_;
};

}  // namespace sylva
