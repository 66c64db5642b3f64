// A recipe's output directory, out/<recipe>/: one directory per node holding exactly that node's
// outputs, what each node last published there (DigestCache's records, .sylva/digests), and the
// explain records (.sylva/<node>.json: the action a node was last built from, for `sylva explain`).
//
// Publishing is atomic per node: a new directory is assembled beside the old one
// (<out>/.<node>.tmp.*: hard links to the blobs, or to the files already there that still hold
// their digests) and swapped in with one FileSystem::replace_dir, so a reader, a kill -9 or a
// second build publishing into the same out dir sees the old directory or the new one, never a
// mix; the build that displaced a directory removes it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/action_cache.h"
#include "pipeline/blob_store.h"
#include "pipeline/digest_cache.h"
#include "pipeline/filesystem.h"

namespace sylva {

class OutDir {
 public:
  // Loads the records of `dir` (a missing or damaged records file is an empty one).
  OutDir(FileSystem& fs, BlobStore& blobs, std::filesystem::path dir);

  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path node_dir(const std::string& node) const { return dir_ / node; }
  std::filesystem::path explain_record(const std::string& node) const;
  DigestCache& digests() { return digests_; }

  // True if <node>/ still holds exactly what `p` says was published there: its directory's stat
  // is unchanged (no file added or removed) and every file holds its digest (stats only).
  bool holds(const std::string& node, const PublishedNode& p);

  // Makes <node>/ hold exactly `outputs`, in one step, unless it already does (stats only, the
  // no-op case). `fresh`: the blobs were stored by this process just now and need no
  // verification; others are re-hashed first and a corrupt one is deleted (BlobStore::
  // materialize). Returns the directory's stat (a default FileInfo if it cannot be trusted next
  // time), or nullopt (and `error`) if a blob is missing or corrupt or the disk refused: the
  // caller rebuilds or fails, and <node>/ is as it was.
  std::optional<FileInfo> publish(const std::string& node, const std::vector<OutputEntry>& outputs,
                                  bool fresh, std::string* error);

  // A node that could not be (re)built must not leave its old outputs under its name: they
  // belong to another action. Its record is forgotten and its directory moved aside in one
  // rename, then deleted.
  void withdraw(const std::string& node);

 private:
  FileSystem& fs_;
  BlobStore& blobs_;
  std::filesystem::path dir_;
  DigestCache digests_;
};

}  // namespace sylva
