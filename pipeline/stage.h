// The stage interface: what every folder under stages/ implements.
//
// A stage is a pure function from typed input artifacts and checked parameters to output
// files. It declares itself once (StageInfo: name, implementation version, parameter schema,
// accepted input types, output type) and is run through run(StageContext&). It must:
//   - read only its declared inputs: upstream artifacts (ctx.inputs(), read with
//     ctx.read_input()) and files named by its kPath/kDir parameters (ctx.read_param_file());
//     nothing else enters the action key. Every read goes through the context, i.e. through the
//     engine's FileSystem: stage tests run on the in-memory fake;
//   - take every random choice from ctx.rng(stream) (seeded by its `seed` parameter);
//   - write outputs only through ctx.write_output()/open_output()/link_output() (output_path()
//     for a library that can only write to a path), into the scratch area; the engine hashes,
//     stores and publishes them atomically, so a failed or interrupted run leaves nothing behind;
//   - report bad input by throwing StageError with a message naming the file and line/element.
// A stage never touches the cache, out/, or another stage's files. Bump `version` whenever a
// change to the implementation can change the bytes it writes: the version is part of the key.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "libs/fileio/file_source.h"
#include "pipeline/param.h"
#include "pipeline/rng.h"
#include "pipeline/value.h"

namespace sylva {

// A user-facing failure of one node (bad input data, impossible parameters). The message is
// printed as `error: node 'X' (stage S): <message>`; no stack trace, exit code 1.
class StageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thrown by StageContext::check_cancelled() after Ctrl-C; the node is reported as interrupted.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("interrupted") {}
};

struct InputSpec {
  std::vector<std::string> types;  // accepted artifact types, e.g. {"tree"}; empty = no inputs
  int min = 0;                     // number of upstream nodes accepted
  int max = 0;                     // -1 = unbounded
  std::string doc;
};

// A problem with parameter values that their schema cannot express (a name's pattern, a pair out
// of order, a list of odd length, a name another parameter must match). `path` leads from the
// node's `with:` to the value: the parameter's name, then field names and list indices as
// decimal strings, e.g. {"species", "1", "name"}; the recipe loader reports it at that value's
// file:line:col (or the nearest enclosing one the recipe spells out).
struct ParamProblem {
  std::vector<std::string> path;
  std::string message;  // what is wrong, without the path: "'a' is the name of species[0] too"
};

// "parameter 'species'[1].name: <message>", the form the recipe loader's own errors take.
std::string param_problem_text(const ParamProblem& p);

struct StageInfo {
  std::string name;     // recipe `stage:` value; [a-z_]+
  int version = 1;      // implementation version, part of the action key
  std::string summary;  // one line for `sylva stages`
  std::vector<ParamSpec> params;
  InputSpec inputs;
  std::string output_type;  // artifact type of this stage's output, e.g. "tree", "mesh"
  // The names its output files may have, as fnmatch patterns ("tree.sylt", "lod*.gltf"); empty:
  // any valid name. A run that declares another name fails; a cached result naming one is
  // not this stage's (a crafted or misfiled action-cache entry) and is never used.
  std::vector<std::string> outputs;
  // Checks of the node's complete, typed parameters beyond the schema, run when the recipe is
  // loaded (so a bad value is a recipe error, exit 2, at its file:line:col) and by the stage
  // itself before it runs. Pure, no inputs; optional.
  std::function<std::vector<ParamProblem>(const Value::Object& params)> check;
  // The same, for checks that need the inputs' artifact types (in the order of `needs`, after
  // its patterns are resolved), e.g. one parameter entry per input of a type. Optional.
  std::function<std::vector<ParamProblem>(const Value::Object& params,
                                          const std::vector<std::string>& input_types)>
      check_inputs;
};

// One file of an upstream artifact, already verified against its digest.
struct ArtifactFile {
  std::string name;            // file name inside the artifact, e.g. "tree.sylt"
  std::filesystem::path path;  // where it is (under out/<recipe>/<node>/): for messages, and for
                               // libraries that can only open a path; read it with read_input()
  std::string digest;          // hex SHA-256
  std::uint64_t size = 0;      // bytes
};

struct InputArtifact {
  std::string node;                 // upstream node name (for messages only: it is not part of the key)
  std::string type;                 // upstream stage's output_type
  std::vector<ArtifactFile> files;  // sorted by name

  // The file with this name, or nullptr.
  const ArtifactFile* file(std::string_view name) const;
  // Files whose name ends with `suffix` (e.g. ".glb"), in name order.
  std::vector<const ArtifactFile*> files_with_suffix(std::string_view suffix) const;
};

// A stage output being written as a stream (StageContext::open_output): for files too big to
// build in memory first (a subdivided tree's GLB). Write through stream(); close() flushes and
// throws StageError if any write failed (the reason, e.g. "No space left on device"). An output
// stream destroyed without close() leaves a file the engine hashes like any other.
class OutputStream {
 public:
  virtual ~OutputStream() = default;
  virtual std::ostream& stream() = 0;
  virtual void close() = 0;
};

class StageContext {
 public:
  virtual ~StageContext() = default;

  virtual const std::string& node_name() const = 0;  // for messages only
  virtual const Value::Object& params() const = 0;   // complete: defaults filled in
  virtual const std::vector<InputArtifact>& inputs() const = 0;

  // The resolved path of the file (kPath) or directory (kDir) named by parameter `param`.
  virtual std::filesystem::path param_file(std::string_view param) const = 0;

  // The node's declared files as a FileSource, for a library that reads a file and the files
  // beside it (a .gltf with its buffers and images): inputs()' files, and the files (kPath) and
  // everything below the directories (kDir) its parameters name, read through the engine's
  // FileSystem. Reading any other path throws std::logic_error (a stage reads only what it
  // declared); exists() is false for it.
  virtual const fileio::FileSource& files() const = 0;
  // The bytes of input file `f` (one of inputs()' files), through the engine's FileSystem.
  // Throws StageError "cannot read input file '<name>' (<path>): <reason>".
  virtual std::string read_input(const ArtifactFile& f) const = 0;
  // The bytes of the file named by kPath parameter `param`, or (kDir) of the file `relative`
  // below the directory it names; at most `max_bytes`. Throws StageError "cannot read '<path>'
  // (parameter '<param>'): <reason>" (a FIFO or device is refused without blocking).
  virtual std::string read_param_file(std::string_view param, const std::filesystem::path& relative = {},
                                      std::uint64_t max_bytes = UINT64_MAX) const = 0;

  // A generator for `stream`, seeded from the node's `seed` parameter (0 when the stage has
  // none). The same (seed, stream) always yields the same sequence.
  virtual Rng rng(std::string_view stream) const = 0;

  // A private, empty directory for temporary files; removed after the run.
  virtual const std::filesystem::path& scratch_dir() const = 0;

  // Path to write output file `name` to ([A-Za-z0-9_.-]+, unique per node). Calling it
  // declares the output; a declared output that is missing after run() fails the node.
  virtual std::filesystem::path output_path(std::string_view name) = 0;
  // Convenience: declare output `name` and write `bytes` to it.
  virtual void write_output(std::string_view name, std::string_view bytes) = 0;
  // Declare output `name` and stream it: the engine hashes the bytes as they are written (it
  // does not read the file again) and never holds the whole file in memory.
  virtual std::unique_ptr<OutputStream> open_output(std::string_view name) = 0;
  // Declare output `name` holding exactly the bytes of input file `f` (a stage passing a file on):
  // a hard link where the file system allows, with f's digest (nothing is copied, read or hashed
  // again). Throws StageError if the link (or the copy it falls back to) fails.
  virtual void link_output(std::string_view name, const ArtifactFile& f) = 0;

  // Throws Cancelled after Ctrl-C; long loops call it now and then.
  virtual void check_cancelled() const = 0;

  // Typed parameter access (the loader guarantees presence and type).
  const Value& param(std::string_view name) const;
  double real(std::string_view name) const { return param(name).as_real(); }
  std::int64_t integer(std::string_view name) const { return param(name).as_int(); }
  bool boolean(std::string_view name) const { return param(name).as_bool(); }
  const std::string& string(std::string_view name) const { return param(name).as_string(); }
};

class Stage {
 public:
  virtual ~Stage() = default;
  virtual const StageInfo& info() const = 0;
  virtual void run(StageContext& ctx) const = 0;
};

}  // namespace sylva
