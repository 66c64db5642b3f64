// The .sylt file: a tree (tree.h) on disk. Versioned, little-endian, exact: every double and
// float is stored as its IEEE-754 bit pattern, so decode(encode(t)) == t bit for bit, and the
// same tree always encodes to the same bytes. Byte layout: docs/tree-format.md.
//
// The reader never trusts the file: every count is checked against the bytes left before
// anything is allocated, the trailing FNV-1a-64 checksum must match, and the decoded tree must
// pass validate_tree(). Any problem throws TreeFormatError with "<source>: byte <offset>: ..."
// (or "<source>: ..." for whole-file problems); it never crashes or reads out of bounds.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "libs/tree/tree.h"

namespace sylva::tree {

inline constexpr char kSyltMagic[8] = {'S', 'Y', 'L', 'T', '\r', '\n', '\x1a', '\n'};
// The version encode_sylt writes. 2: leaf kind, atlas grid and coverage, bark tint; 3: the
// imported mesh (Tree::source) after the needles. decode_sylt reads versions
// kSyltOldestVersion..kSyltVersion (a version 2 file decodes with an empty source).
inline constexpr std::uint32_t kSyltVersion = 3;
inline constexpr std::uint32_t kSyltOldestVersion = 2;

class TreeFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The .sylt bytes of `tree`. Throws std::invalid_argument (listing validate_tree's messages)
// if the tree breaks an invariant: an invalid tree is never written.
std::string encode_sylt(const Tree& tree);

// Parses .sylt bytes. `source` names the bytes in error messages (usually the file path).
Tree decode_sylt(std::string_view bytes, std::string_view source = "<memory>");

// File convenience wrappers. write_sylt throws std::runtime_error on I/O failure;
// read_sylt throws TreeFormatError for unreadable, truncated or corrupt files.
void write_sylt(const std::filesystem::path& path, const Tree& tree);
Tree read_sylt(const std::filesystem::path& path);

// FNV-1a 64-bit hash (the .sylt checksum); exposed for tests and tools.
std::uint64_t fnv1a64(std::string_view bytes);

}  // namespace sylva::tree
