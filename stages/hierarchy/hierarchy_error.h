// The one exception the hierarchy core throws: a problem with the input geometry or the options,
// worded for people; the adapter prefixes the file it read (docs/stages/hierarchy.md).
#pragma once

#include <stdexcept>
#include <string>

namespace sylva::hierarchy {

class HierarchyError : public std::runtime_error {
 public:
  explicit HierarchyError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace sylva::hierarchy
