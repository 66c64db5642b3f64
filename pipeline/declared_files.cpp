#include "pipeline/declared_files.h"

#include <stdexcept>

namespace sylva {

namespace fs = std::filesystem;

bool DeclaredFiles::declared(const fs::path& normal) const {
  if (files_.count(normal)) return true;
  for (const auto& d : dirs_) {
    const auto rel = normal.lexically_relative(d);
    if (!rel.empty() && *rel.begin() != ".." && !rel.is_absolute()) return true;
  }
  return false;
}

std::string DeclaredFiles::read(const fs::path& path) const {
  const fs::path normal = path.lexically_normal();
  if (!declared(normal))
    throw std::logic_error("the stage read '" + path.string() + "', which is not one of its declared inputs");
  std::string why;
  auto bytes = fs_.read(normal, &why);
  if (!bytes) throw fileio::FileReadError(path, why);
  return std::move(*bytes);
}

bool DeclaredFiles::exists(const fs::path& path) const {
  const fs::path normal = path.lexically_normal();
  return declared(normal) && fs_.stat(normal).has_value();
}

}  // namespace sylva
