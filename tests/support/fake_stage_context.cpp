#include "tests/support/fake_stage_context.h"

#include <sstream>
#include <stdexcept>

#include "pipeline/digest.h"

namespace sylva::test {

namespace fs = std::filesystem;

namespace {

// A stream that hands its bytes to the file system on close(), as the engine's streams do.
class BufferedOutput final : public OutputStream {
 public:
  BufferedOutput(FileSystem& fsys, fs::path path) : fs_(fsys), path_(std::move(path)) {}
  std::ostream& stream() override { return buf_; }
  void close() override {
    std::string why;
    if (!fs_.write_atomic(path_, buf_.str(), /*durable=*/false, &why))
      throw StageError("cannot write output '" + path_.filename().string() + "': " + why);
  }

 private:
  FileSystem& fs_;
  fs::path path_;
  std::ostringstream buf_;
};

}  // namespace

FakeStageContext::FakeStageContext(const Stage& stage, const std::vector<Input>& inputs, fs::path out,
                                   const Value::Object& overrides, FileSystem* fsys)
    : stage_(stage),
      own_fs_(fsys ? nullptr : std::make_unique<RealFileSystem>()),
      fs_(fsys ? fsys : own_fs_.get()),
      files_(std::make_unique<DeclaredFiles>(*fs_)),
      out_(std::move(out)),
      scratch_(out_.parent_path() / (out_.filename().string() + ".scratch")) {
  for (const ParamSpec& p : stage.info().params)
    if (!p.required()) params_[p.name] = p.default_value;
  for (const auto& [k, v] : overrides) params_[k] = v;
  if (auto it = params_.find("seed"); it != params_.end() && it->second.is_int())
    seed = static_cast<std::uint64_t>(it->second.as_int());
  fs_->make_dirs(out_);
  fs_->make_dirs(scratch_);
  for (const Input& i : inputs) {
    std::map<std::string, fs::path> files;
    for (const auto& n : fs_->list(i.dir)) files[n] = i.dir / n;
    add_input(i.node, i.type, files);
  }
}

FakeStageContext::~FakeStageContext() { fs_->remove_all(scratch_); }

void FakeStageContext::add_input(std::string node, std::string type,
                                 const std::map<std::string, fs::path>& files) {
  InputArtifact in{std::move(node), std::move(type), {}};
  for (const auto& [n, p] : files) {
    auto d = fs_->digest(p);
    in.files.push_back({n, p, d ? d->hash : "0", d ? d->size : 0});
  }
  add_input(std::move(in));
}

void FakeStageContext::add_input(InputArtifact artifact) {
  for (const auto& f : artifact.files) files_->allow_file(f.path);
  inputs_.push_back(std::move(artifact));
}

void FakeStageContext::set_file(const std::string& param, const fs::path& path) {
  file_params_[param] = path;
  params_[param] = Value(path.string());
  bool is_dir = false;
  for (const ParamSpec& p : stage_.info().params)
    if (p.name == param) {
      is_dir = p.type == ParamType::kDir;
      if (auto folder = param_folder(p, path)) files_->allow_dir(*folder);  // as the engine does
    }
  if (is_dir)
    files_->allow_dir(path);
  else
    files_->allow_file(path);
}

fs::path FakeStageContext::param_file(std::string_view param) const {
  auto it = file_params_.find(std::string(param));
  if (it == file_params_.end())
    throw std::logic_error("no file parameter '" + std::string(param) + "' in this test");
  return it->second;
}

std::string FakeStageContext::read_input(const ArtifactFile& f) const {
  std::string why;
  auto bytes = fs_->read(f.path, &why);
  if (!bytes) throw StageError("cannot read input file '" + f.name + "' (" + f.path.string() + "): " + why);
  return std::move(*bytes);
}

std::string FakeStageContext::read_param_file(std::string_view param, const fs::path& relative,
                                              std::uint64_t max_bytes) const {
  const fs::path p = relative.empty() ? param_file(param) : param_file(param) / relative;
  std::string why;
  auto bytes = fs_->read(p, &why, max_bytes);
  if (!bytes)
    throw StageError("cannot read '" + p.string() + "' (parameter '" + std::string(param) + "'): " + why);
  return std::move(*bytes);
}

fs::path FakeStageContext::output_path(std::string_view name) {
  declared.insert(std::string(name));
  outputs.emplace_back(name);
  return out_ / std::string(name);
}

void FakeStageContext::write_output(std::string_view name, std::string_view bytes) {
  std::string why;
  if (!fs_->write_atomic(output_path(name), bytes, /*durable=*/false, &why))
    throw StageError("cannot write output '" + std::string(name) + "': " + why);
}

std::unique_ptr<OutputStream> FakeStageContext::open_output(std::string_view name) {
  return std::make_unique<BufferedOutput>(*fs_, output_path(name));
}

void FakeStageContext::link_output(std::string_view name, const ArtifactFile& f) {
  std::string why;
  if (!fs_->link_or_copy(f.path, output_path(name), nullptr, &why))
    throw StageError("cannot write output '" + std::string(name) + "' from input file '" + f.name +
                     "': " + why);
}

void FakeStageContext::check_cancelled() const {
  if (cancel && cancel->load()) throw Cancelled();
}

std::string FakeStageContext::output(const std::string& n) {
  std::string why;
  auto bytes = fs_->read(out_ / n, &why);
  if (!bytes) throw std::runtime_error("no output '" + n + "': " + why);
  return std::move(*bytes);
}

}  // namespace sylva::test
