#include "pipeline/registry.h"

#include <stdexcept>

namespace sylva {

void StageRegistry::add(std::unique_ptr<Stage> stage) {
  const std::string name = stage->info().name;
  if (!stages_.emplace(name, std::move(stage)).second)
    throw std::logic_error("stage registered twice: " + name);
}

const Stage* StageRegistry::find(std::string_view name) const {
  auto it = stages_.find(name);
  return it == stages_.end() ? nullptr : it->second.get();
}

std::vector<std::string> StageRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [n, s] : stages_) out.push_back(n);
  return out;
}

std::vector<const Stage*> StageRegistry::all() const {
  std::vector<const Stage*> out;
  for (const auto& [n, s] : stages_) out.push_back(s.get());
  return out;
}

}  // namespace sylva
