// The one StageContext for running a stage's adapter in a test, on a FileSystem the test chooses:
// the real disk (a temporary directory; the default) or the in-memory fake
// (tests/support/fake_filesystem.h), which records every read and write. Parameters: the
// stage's defaults plus overrides; inputs: every file of a directory per artifact (or files
// given one by one); outputs written, streamed and linked into `out` through the file system,
// as the engine does (pipeline/node_context.h). The seed is the `seed` parameter when the stage
// has one (0 otherwise), as in the engine.
#pragma once

#include <atomic>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "pipeline/declared_files.h"
#include "pipeline/filesystem.h"
#include "pipeline/stage.h"

namespace sylva::test {

class FakeStageContext : public StageContext {
 public:
  struct Input {
    std::string node, type;
    std::filesystem::path dir;  // every file in it, on the context's file system
  };

  // `fsys` (not owned; nullptr: a RealFileSystem of the context's own) holds the inputs and
  // receives the outputs; `out` is created.
  FakeStageContext(const Stage& stage, const std::vector<Input>& inputs, std::filesystem::path out,
                   const Value::Object& overrides = {}, FileSystem* fsys = nullptr);
  ~FakeStageContext() override;

  // Adds an input artifact of files already on the file system (name -> path), in name order.
  void add_input(std::string node, std::string type,
                 const std::map<std::string, std::filesystem::path>& files);
  // Adds an input artifact as given (its digests and sizes are not checked).
  void add_input(InputArtifact artifact);
  // Names the file (kPath) or directory (kDir, by the stage's schema) behind a file parameter;
  // its value in params() becomes the path, as the recipe loader resolves it.
  void set_file(const std::string& param, const std::filesystem::path& path);

  const std::string& node_name() const override { return name; }
  const Value::Object& params() const override { return params_; }
  const std::vector<InputArtifact>& inputs() const override { return inputs_; }
  std::filesystem::path param_file(std::string_view param) const override;
  const fileio::FileSource& files() const override { return *files_; }
  std::string read_input(const ArtifactFile& f) const override;
  std::string read_param_file(std::string_view param, const std::filesystem::path& relative = {},
                              std::uint64_t max_bytes = UINT64_MAX) const override;
  Rng rng(std::string_view stream) const override { return Rng(seed, stream); }
  const std::filesystem::path& scratch_dir() const override { return scratch_; }
  std::filesystem::path output_path(std::string_view name) override;
  void write_output(std::string_view name, std::string_view bytes) override;
  std::unique_ptr<OutputStream> open_output(std::string_view name) override;
  void link_output(std::string_view name, const ArtifactFile& f) override;
  void check_cancelled() const override;

  FileSystem& fs() { return *fs_; }
  // The bytes of output `name` as the stage wrote it.
  std::string output(const std::string& name);

  std::string name = "node";
  std::uint64_t seed = 0;                     // set from the `seed` parameter by the constructor
  const std::atomic<bool>* cancel = nullptr;  // raised: check_cancelled() throws Cancelled
  std::set<std::string> declared;             // every output the stage declared
  std::vector<std::string> outputs;           // the same, in the order declared (repeats kept)

 private:
  const Stage& stage_;
  std::unique_ptr<FileSystem> own_fs_;
  FileSystem* fs_;
  std::unique_ptr<DeclaredFiles> files_;
  Value::Object params_;
  std::vector<InputArtifact> inputs_;
  std::map<std::string, std::filesystem::path> file_params_;
  std::filesystem::path out_, scratch_;
};

}  // namespace sylva::test
