// Where a library's reader gets the bytes of the file it reads and of the files beside it (a
// .gltf's buffers and images): the disk through the one checked reader (disk_files()), or a
// stage's declared inputs through its StageContext (StageContext::files(), backed by the engine's
// FileSystem, so a stage's tests run on the in-memory fake and an undeclared read is refused).
#pragma once

#include <filesystem>
#include <string>

#include "libs/fileio/read_file.h"

namespace sylva::fileio {

class FileSource {
 public:
  virtual ~FileSource() = default;
  // The bytes of `path`. Throws FileReadError ("<path>: error: <reason>") if it cannot be read.
  virtual std::string read(const std::filesystem::path& path) const = 0;
  // True if `path` can be read through this source (nothing is opened).
  virtual bool exists(const std::filesystem::path& path) const = 0;
};

// The disk, through read_file() and exists(). Stateless; one instance for the process.
const FileSource& disk_files();

}  // namespace sylva::fileio
