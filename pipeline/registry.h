// The set of stages a binary knows. The shipped `sylva` registers the real stages in
// stages/register_stages.cpp (the only place they are wired); tests register their own.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/stage.h"

namespace sylva {

class StageRegistry {
 public:
  // Takes ownership. A second stage with the same name is a programming error (throws).
  void add(std::unique_ptr<Stage> stage);
  const Stage* find(std::string_view name) const;  // nullptr if unknown
  std::vector<std::string> names() const;          // sorted
  std::vector<const Stage*> all() const;           // sorted by name

 private:
  std::map<std::string, std::unique_ptr<Stage>, std::less<>> stages_;
};

}  // namespace sylva
