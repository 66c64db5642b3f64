#include "pipeline/stage.h"

namespace sylva {

const ArtifactFile* InputArtifact::file(std::string_view name) const {
  for (const auto& f : files)
    if (f.name == name) return &f;
  return nullptr;
}

std::vector<const ArtifactFile*> InputArtifact::files_with_suffix(std::string_view suffix) const {
  std::vector<const ArtifactFile*> out;
  for (const auto& f : files)
    if (f.name.size() >= suffix.size() &&
        f.name.compare(f.name.size() - suffix.size(), suffix.size(), suffix) == 0)
      out.push_back(&f);
  return out;
}

std::string param_problem_text(const ParamProblem& p) {
  std::string where = "parameter";
  for (std::size_t i = 0; i < p.path.size(); ++i) {
    const std::string& e = p.path[i];
    if (i == 0)
      where += " '" + e + "'";
    else if (!e.empty() && e.find_first_not_of("0123456789") == std::string::npos)
      where += "[" + e + "]";
    else
      where += "." + e;
  }
  return where + ": " + p.message;
}

const Value& StageContext::param(std::string_view name) const {
  const auto& p = params();
  auto it = p.find(std::string(name));
  if (it == p.end()) throw std::logic_error("stage read undeclared parameter '" + std::string(name) + "'");
  return it->second;
}

}  // namespace sylva
