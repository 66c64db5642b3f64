#include "pipeline/project_root.h"

#include <sys/stat.h>

#include <mutex>
#include <unordered_map>

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

// A path with no empty, "." or ".." element and no trailing "/" (absolute or relative): it is
// lexically normal and its last element names an entry of its parent directory.
bool plain(std::string_view s) {
  std::size_t i = !s.empty() && s[0] == '/' ? 1 : 0;
  if (i >= s.size()) return false;
  for (;;) {
    const std::size_t j = s.find('/', i);
    const std::string_view e = s.substr(i, j == std::string_view::npos ? std::string_view::npos : j - i);
    if (e.empty() || e == "." || e == "..") return false;
    if (j == std::string_view::npos) return true;
    i = j + 1;
  }
}

// `r` is `dir` or below it; both absolute and lexically normal, `dir` without a trailing "/".
bool below_str(std::string_view dir, std::string_view r) {
  if (dir == "/") return !r.empty() && r[0] == '/';
  return r.size() >= dir.size() && r.compare(0, dir.size(), dir) == 0 &&
         (r.size() == dir.size() || r[dir.size()] == '/');
}

}  // namespace

struct ProjectRoot::DirCache {
  std::mutex mu;
  std::unordered_map<std::string, std::string> dirs;  // directory as given -> resolved
};

ProjectRoot::ProjectRoot(const std::vector<fs::path>& dirs)
    : confined_(true), resolved_dirs_(std::make_shared<DirCache>()) {
  for (const auto& d : dirs) {
    dirs_.push_back(resolved(d));
    std::string s = dirs_.back().native();
    while (s.size() > 1 && s.back() == '/') s.pop_back();
    dir_strings_.push_back(std::move(s));
  }
}

bool ProjectRoot::contains(const fs::path& p, bool known_not_link) const {
  if (!confined_) return true;
  // resolved(p) costs a getcwd and a readlink per path element. For a plain path whose last
  // element is not a symbolic link (one lstat) it equals resolved(parent) + "/" + name, and
  // each parent is resolved once. Anything else ("..", ".", a trailing "/", a link) takes the
  // full resolution. The working directory never changes while sylva runs, so a relative
  // parent names the same directory every time.
  const std::string& s = p.native();
  struct stat st {};
  if (plain(s) && (known_not_link || ::lstat(s.c_str(), &st) != 0 || !S_ISLNK(st.st_mode))) {
    const std::size_t slash = s.rfind('/');
    const std::string parent = slash == std::string::npos ? std::string(".")
                               : slash == 0               ? std::string("/")
                                                          : s.substr(0, slash);
    std::string r;
    {
      std::lock_guard lock(resolved_dirs_->mu);
      auto [it, added] = resolved_dirs_->dirs.try_emplace(parent);
      if (added) {
        it->second = resolved(parent).native();
        while (it->second.size() > 1 && it->second.back() == '/') it->second.pop_back();
      }
      r = it->second;
    }
    if (r.empty() || r[0] != '/') return false;  // unresolvable: judged as outside
    if (r != "/") r += '/';
    r.append(s, slash == std::string::npos ? 0 : slash + 1, std::string::npos);
    for (const auto& d : dir_strings_)
      if (below_str(d, r)) return true;
    return false;
  }
  const fs::path r = resolved(p);
  for (const auto& d : dirs_)
    if (below(d, r)) return true;
  return false;
}

std::string ProjectRoot::outside_message(const fs::path& p) const {
  std::string roots;
  for (const auto& d : dirs_) roots += (roots.empty() ? "'" : ", '") + excerpt(d.string(), 200) + "'";
  return "'" + excerpt(p.string(), 200) + "' is outside the project root" + (dirs_.size() > 1 ? "s " : " ") +
         roots +
         " (a recipe may only name files below its directory or the directories its 'root:' key "
         "declares; pass --allow-outside-root to trust this recipe)";
}

}  // namespace sylva
