// Why outputs are hashed while written: a subdivided tree's GLB is hundreds of megabytes, and
// reading it back only to hash it doubled the I/O of storing it. Why link_output exists: stages
// that pass an input on (the forest's level files, the pack's atlases) copied and re-hashed
// bytes whose digest the engine already had.
#include "pipeline/node_context.h"

#include <functional>
#include <streambuf>

#include "pipeline/cache.h"

namespace sylva {

namespace fs = std::filesystem;

namespace {

// A streamed output: buffered writes to the scratch file through the FileSystem, hashed on the
// way. close() hands the digest to the context, so storing the output reads nothing.
class HashingStream final : public OutputStream, private std::streambuf {
 public:
  HashingStream(std::unique_ptr<WritableFile> file, std::string name,
                std::function<void(const std::string&, const Digest&)> done)
      : out_(this), file_(std::move(file)), name_(std::move(name)), done_(std::move(done)), buf_(1 << 20) {
    setp(buf_.data(), buf_.data() + buf_.size());
  }
  std::ostream& stream() override { return out_; }
  void close() override {
    drain();
    std::string why;
    const bool closed = file_->close(&why);
    if (!error_.empty()) why = error_;  // the first failure says why
    if (!error_.empty() || !closed) throw StageError("cannot write output '" + name_ + "': " + why);
    done_(name_, Digest{hash_.finish_hex(), total_});
  }

 private:
  bool drain() {
    const std::size_t n = static_cast<std::size_t>(pptr() - pbase());
    if (error_.empty() && !file_->append(pbase(), n, &error_) && error_.empty()) error_ = "write failed";
    hash_.update(pbase(), n);
    total_ += n;
    setp(buf_.data(), buf_.data() + buf_.size());
    return error_.empty();
  }
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

  std::ostream out_;
  std::unique_ptr<WritableFile> file_;
  std::string name_;
  std::function<void(const std::string&, const Digest&)> done_;
  std::vector<char> buf_;
  std::string error_;
  Sha256 hash_;
  std::uint64_t total_ = 0;
};

}  // namespace

NodeContext::NodeContext(FileSystem& fs, const NodeDecl& node, std::vector<InputArtifact> inputs,
                         fs::path work, fs::path out, const std::atomic<bool>* cancel)
    : fs_(fs),
      node_(node),
      inputs_(std::move(inputs)),
      work_(std::move(work)),
      out_(std::move(out)),
      cancel_(cancel),
      files_(fs) {
  auto it = node.params.find("seed");
  if (it != node.params.end() && it->second.is_int()) seed_ = static_cast<std::uint64_t>(it->second.as_int());
  for (const auto& in : inputs_)
    for (const auto& f : in.files) files_.allow_file(f.path);
  for (const auto& [param, path] : node.files) {
    bool is_dir = false;
    for (const auto& p : node.stage->info().params)
      if (p.name == param) {
        is_dir = p.type == ParamType::kDir;
        if (auto folder = param_folder(p, path)) files_.allow_dir(*folder);  // in the key too
      }
    if (is_dir)
      files_.allow_dir(path);
    else
      files_.allow_file(path);
  }
}

fs::path NodeContext::param_file(std::string_view param) const {
  auto it = node_.files.find(std::string(param));
  if (it == node_.files.end())
    throw std::logic_error("stage asked for undeclared file parameter '" + std::string(param) + "'");
  return it->second;
}

std::string NodeContext::read_input(const ArtifactFile& f) const {
  std::string why;
  auto bytes = fs_.read(f.path, &why);
  if (!bytes) throw StageError("cannot read input file '" + f.name + "' (" + f.path.string() + "): " + why);
  return std::move(*bytes);
}

std::string NodeContext::read_param_file(std::string_view param, const fs::path& relative,
                                         std::uint64_t max_bytes) const {
  fs::path p = param_file(param);
  if (!relative.empty()) {
    // A file below a kDir parameter's directory: never a path that leaves it.
    const fs::path rel = relative.lexically_normal();
    if (rel.is_absolute() || rel.empty() || *rel.begin() == "..")
      throw std::logic_error("stage asked for '" + relative.string() + "', which is not below parameter '" +
                             std::string(param) + "'");
    p /= rel;
  }
  std::string why;
  auto bytes = fs_.read(p, &why, max_bytes);
  if (!bytes)
    throw StageError("cannot read '" + p.string() + "' (parameter '" + std::string(param) + "'): " + why);
  return std::move(*bytes);
}

fs::path NodeContext::output_path(std::string_view name) {
  const std::string n(name);
  if (!is_valid_name(name)) throw std::logic_error("invalid output file name '" + n + "'");
  if (!output_name_declared(n, node_.stage->info().outputs))
    throw std::logic_error("stage '" + node_.stage->info().name + "' wrote output '" + n +
                           "', which its StageInfo::outputs does not declare");
  std::lock_guard l(mu_);
  declared_.insert(n);
  known_.erase(n);  // whatever is written now must be hashed
  return out_ / n;
}

void NodeContext::write_output(std::string_view name, std::string_view bytes) {
  // Not fsynced here: the DurableBatch makes the blob durable before any result names it.
  const fs::path p = output_path(name);
  std::string why;
  if (!fs_.write_atomic(p, bytes, /*durable=*/false, &why))
    throw StageError("cannot write output '" + std::string(name) + "': " + why);
  std::lock_guard l(mu_);
  known_[std::string(name)] = digest_bytes(bytes);
}

std::unique_ptr<OutputStream> NodeContext::open_output(std::string_view name) {
  const fs::path p = output_path(name);
  std::string why;
  auto file = fs_.create(p, &why);
  if (!file) throw StageError("cannot create output '" + std::string(name) + "': " + why);
  return std::make_unique<HashingStream>(std::move(file), std::string(name),
                                         [this](const std::string& n, const Digest& d) {
                                           std::lock_guard l(mu_);
                                           known_[n] = d;
                                         });
}

void NodeContext::link_output(std::string_view name, const ArtifactFile& f) {
  const fs::path p = output_path(name);
  std::string why;
  if (!fs_.link_or_copy(f.path, p, nullptr, &why))
    throw StageError("cannot write output '" + std::string(name) + "' from input file '" + f.name +
                     "': " + why);
  std::lock_guard l(mu_);
  known_[std::string(name)] = Digest{f.digest, f.size};
}

void NodeContext::check_cancelled() const {
  if (cancel_ && cancel_->load()) throw Cancelled();
}

std::optional<Digest> NodeContext::known_digest(const std::string& name) {
  std::lock_guard l(mu_);
  auto it = known_.find(name);
  if (it == known_.end()) return std::nullopt;
  return it->second;
}

}  // namespace sylva
