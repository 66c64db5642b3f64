// The StageContext a stage sees when the engine runs it (LocalRunner): everything it may touch,
// nothing else. Inputs are read, and outputs written, streamed or linked, through the engine's
// FileSystem, into a private scratch directory; the digest of every output written through the
// context is computed on the way, so storing it reads nothing again.
#pragma once

#include <atomic>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "pipeline/declared_files.h"
#include "pipeline/digest.h"
#include "pipeline/filesystem.h"
#include "pipeline/recipe.h"
#include "pipeline/stage.h"

namespace sylva {

class NodeContext final : public StageContext {
 public:
  // `work`: the stage's scratch directory; `out`: where its outputs are written (both empty,
  // existing, on `fs`). `cancel` (may be null) is raised by Ctrl-C.
  NodeContext(FileSystem& fs, const NodeDecl& node, std::vector<InputArtifact> inputs,
              std::filesystem::path work, std::filesystem::path out, const std::atomic<bool>* cancel);

  const std::string& node_name() const override { return node_.name; }
  const Value::Object& params() const override { return node_.params; }
  const std::vector<InputArtifact>& inputs() const override { return inputs_; }
  std::filesystem::path param_file(std::string_view param) const override;
  const fileio::FileSource& files() const override { return files_; }
  std::string read_input(const ArtifactFile& f) const override;
  std::string read_param_file(std::string_view param, const std::filesystem::path& relative = {},
                              std::uint64_t max_bytes = UINT64_MAX) const override;
  Rng rng(std::string_view stream) const override { return Rng(seed_, stream); }
  const std::filesystem::path& scratch_dir() const override { return work_; }
  std::filesystem::path output_path(std::string_view name) override;
  void write_output(std::string_view name, std::string_view bytes) override;
  std::unique_ptr<OutputStream> open_output(std::string_view name) override;
  void link_output(std::string_view name, const ArtifactFile& f) override;
  void check_cancelled() const override;

  // The output names the stage declared, sorted.
  const std::set<std::string>& declared() const { return declared_; }
  // The digest of output `name` if it is known without reading it (written, streamed or linked
  // through the context and not declared again since).
  std::optional<Digest> known_digest(const std::string& name);

 private:
  FileSystem& fs_;
  const NodeDecl& node_;
  std::vector<InputArtifact> inputs_;
  std::filesystem::path work_, out_;
  const std::atomic<bool>* cancel_;
  std::uint64_t seed_ = 0;
  DeclaredFiles files_;
  std::mutex mu_;
  std::set<std::string> declared_;
  std::map<std::string, Digest> known_;
};

}  // namespace sylva
