#include "pipeline/project_root.h"

#include "pipeline/diagnostic.h"

namespace sylva {

namespace fs = std::filesystem;

namespace {

fs::path resolved(const fs::path& p) {
  std::error_code ec;
  fs::path abs = fs::absolute(p, ec);
  if (ec) abs = p;
  // weakly_canonical resolves the links of the part that exists: a link inside the project
  // pointing outside it is judged by where it points.
  fs::path c = fs::weakly_canonical(abs, ec);
  return (ec ? abs : c).lexically_normal();
}

bool below(const fs::path& dir, const fs::path& p) {
  auto d = dir.begin(), x = p.begin();
  for (; d != dir.end(); ++d, ++x) {
    if (d->empty() && std::next(d) == dir.end()) break;  // "/a/b/" ends with an empty element
    if (x == p.end() || *d != *x) return false;
  }
  return true;
}

}  // namespace

ProjectRoot::ProjectRoot(const std::vector<fs::path>& dirs) : confined_(true) {
  for (const auto& d : dirs) dirs_.push_back(resolved(d));
}

bool ProjectRoot::contains(const fs::path& p) const {
  if (!confined_) return true;
  const fs::path r = resolved(p);
  for (const auto& d : dirs_)
    if (below(d, r)) return true;
  return false;
}

std::string ProjectRoot::outside_message(const fs::path& p) const {
  std::string roots;
  for (const auto& d : dirs_) roots += (roots.empty() ? "'" : ", '") + excerpt(d.string(), 200) + "'";
  return "'" + excerpt(p.string(), 200) + "' is outside the project root" + (dirs_.size() > 1 ? "s " : " ") + roots +
         " (a recipe may only name files below its directory or the directories its 'root:' key "
         "declares; pass --allow-outside-root to trust this recipe)";
}

}  // namespace sylva
