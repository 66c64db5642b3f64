#include "libs/fileio/file_source.h"

namespace sylva::fileio {

namespace {

class DiskFiles final : public FileSource {
 public:
  std::string read(const std::filesystem::path& path) const override { return read_file(path); }
  bool exists(const std::filesystem::path& path) const override { return fileio::exists(path); }
};

}  // namespace

const FileSource& disk_files() {
  static const DiskFiles files;
  return files;
}

}  // namespace sylva::fileio
