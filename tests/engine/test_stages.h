// Stages for engine tests only (never registered in the shipped binary). They do real, checkable
// work on text so tests can assert exact output bytes, run counts and failures.
#pragma once

#include <oneapi/tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

#include "pipeline/registry.h"
#include "pipeline/stage.h"

namespace sylva::test {

// Counts stage runs per node, so a test can say exactly which nodes ran.
struct RunLog {
  std::mutex mu;
  std::map<std::string, int> runs;
  void record(const std::string& node) {
    std::lock_guard lock(mu);
    ++runs[node];
  }
  int count(const std::string& node) {
    std::lock_guard lock(mu);
    return runs.count(node) ? runs[node] : 0;
  }
  int total() {
    std::lock_guard lock(mu);
    int t = 0;
    for (auto& [k, v] : runs) t += v;
    return t;
  }
  void clear() {
    std::lock_guard lock(mu);
    runs.clear();
  }
};

// What every test stage shares: its StageInfo (the constructor sets name, summary, version 1, no
// inputs and output type "text"; a stage changes what differs) and the RunLog its runs are
// recorded in (null: not recorded).
class TestStage : public Stage {
 public:
  const StageInfo& info() const override { return info_; }

 protected:
  TestStage(std::string name, std::string summary, RunLog* log = nullptr) : log_(log) {
    info_.name = std::move(name);
    info_.version = 1;
    info_.summary = std::move(summary);
    info_.inputs = {{}, 0, 0, ""};
    info_.output_type = "text";
  }
  void record(const StageContext& ctx) const {
    if (log_) log_->record(ctx.node_name());
  }

  RunLog* log_;
  StageInfo info_;
};

// `text`: no inputs; writes `text` followed by `count` pseudo-random numbers from the seed.
class TextStage final : public TestStage {
 public:
  explicit TextStage(RunLog* log) : TestStage("text", "writes a line of text (test stage)", log) {
    info_.params = {
        Param::string("text", "hello").describe("the text"),
        Param::integer("seed", 1).range(0, 1e9).describe("random seed"),
        Param::integer("count", 0).range(0, 1000).describe("random numbers to append"),
        Param::real("scale", 1.0).range(0.0, 10.0).describe("a real parameter"),
        Param::choice("mode", {"plain", "upper"}, "plain").describe("case"),
        Param::boolean("fail", false).describe("fail with a StageError"),
        Param::integer("sleep_ms", 0).range(0, 60000).describe("sleep before writing"),
        Param::real_list("weights", Value::List{}).describe("a list"),
        Param::object("camera", {Param::real("fov_y_deg", 45.0).range(1, 179),
                                 Param::integer("height_px", 1080).range(1, 100000)}),
        Param::object_list("items", {Param::string("name"), Param::real("weight", 1.0).range(0, 10)}),
    };
    // Checks beyond the schema (StageInfo::check): item names unique, and one forbidden text.
    info_.check = [](const Value::Object& p) {
      std::vector<ParamProblem> out;
      const Value::List& items = p.at("items").as_list();
      for (std::size_t i = 0; i < items.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
          if (items[i].as_object().at("name") == items[j].as_object().at("name"))
            out.push_back({{"items", std::to_string(i), "name"},
                           "'" + items[i].as_object().at("name").as_string() + "' is the name of items[" +
                               std::to_string(j) + "] too"});
      if (p.at("text").as_string() == "forbidden") out.push_back({{"text"}, "'forbidden' is not allowed"});
      return out;
    };
  }
  void run(StageContext& ctx) const override {
    record(ctx);
    for (std::int64_t t = 0; t < ctx.integer("sleep_ms"); t += 5) {
      ctx.check_cancelled();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (ctx.boolean("fail")) throw StageError("asked to fail");
    std::string s = ctx.string("text");
    if (ctx.string("mode") == "upper")
      for (auto& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    Rng rng = ctx.rng("numbers");
    for (std::int64_t i = 0; i < ctx.integer("count"); ++i) s += " " + std::to_string(rng.next_u64() % 1000);
    ctx.write_output("out.txt", s + "\n");
  }
};

// `concat`: any number of text inputs; writes their out.txt in `needs` order plus `suffix`.
class ConcatStage final : public TestStage {
 public:
  explicit ConcatStage(RunLog* log) : TestStage("concat", "concatenates text inputs (test stage)", log) {
    info_.params = {Param::string("suffix", "").describe("appended text"),
                    Param::boolean("fail", false).describe("fail with a StageError")};
    info_.inputs = {{"text"}, 1, -1, "texts"};
    // A check that needs the inputs (StageInfo::check_inputs): a suffix "#N" must name the count.
    info_.check_inputs = [](const Value::Object& p, const std::vector<std::string>& types) {
      std::vector<ParamProblem> out;
      const std::string& s = p.at("suffix").as_string();
      if (s.starts_with("#") && s != "#" + std::to_string(types.size()))
        out.push_back(
            {{"suffix"}, "says " + s.substr(1) + " inputs, the node has " + std::to_string(types.size())});
      return out;
    };
  }
  void run(StageContext& ctx) const override {
    record(ctx);
    if (ctx.boolean("fail")) throw StageError("asked to fail");
    std::string s;
    for (const auto& in : ctx.inputs()) s += ctx.read_input(*in.file("out.txt"));
    ctx.write_output("out.txt", s + ctx.string("suffix"));
  }
};

// `readfile`: copies the file named by its `file` parameter (a declared file input).
class ReadFileStage final : public TestStage {
 public:
  explicit ReadFileStage(RunLog* log) : TestStage("readfile", "copies a file (test stage)", log) {
    info_.params = {Param::path("file").describe("file to copy")};
  }
  void run(StageContext& ctx) const override {
    record(ctx);
    ctx.write_output("out.txt", ctx.read_param_file("file"));
  }
};

// `readmodel`: like readfile, for a "model" whose .gltf brings its folder
// (ParamSpec::with_folder_for); appends the file `sibling` (relative to the model's folder, read
// through ctx.files()) when that parameter is not empty.
class ReadModelStage final : public TestStage {
 public:
  explicit ReadModelStage(RunLog* log)
      : TestStage("readmodel", "copies a model and a sibling (test stage)", log) {
    info_.params = {Param::path("file").with_folder_for({".gltf"}).describe("model to copy"),
                    Param::string("sibling", "").describe("a file beside it to append")};
  }
  void run(StageContext& ctx) const override {
    record(ctx);
    std::string s = ctx.files().read(ctx.param_file("file"));
    if (!ctx.string("sibling").empty())
      s += ctx.files().read(ctx.param_file("file").parent_path() / ctx.string("sibling"));
    ctx.write_output("out.txt", s);
  }
};

// `mesh_only`: accepts only "mesh" inputs (to test input type errors); never run.
class MeshOnlyStage final : public TestStage {
 public:
  MeshOnlyStage() : TestStage("mesh_only", "accepts meshes (test stage)") {
    info_.inputs = {{"mesh"}, 1, 1, "a mesh"};
    info_.output_type = "mesh";
  }
  void run(StageContext&) const override {}
};

// `nested`: writes `text` after a parallel loop of its own (oneTBB), as mesh and lod run them:
// `items` tiny tasks of `micros` each. Nodes with the same text share one action key.
class NestedParallelStage final : public TestStage {
 public:
  explicit NestedParallelStage(RunLog* log)
      : TestStage("nested", "a parallel loop inside a node (test stage)", log) {
    info_.params = {Param::string("text", "n").describe("the text"),
                    Param::integer("items", 64).range(1, 100000).describe("inner tasks"),
                    Param::integer("micros", 200).range(0, 100000).describe("work per inner task")};
    info_.inputs = {{"text"}, 0, -1, "any texts"};
    info_.outputs = {"out.txt"};
  }
  void run(StageContext& ctx) const override {
    record(ctx);
    const auto micros = std::chrono::microseconds(ctx.integer("micros"));
    std::atomic<std::int64_t> sum{0};
    tbb::parallel_for(std::int64_t{0}, ctx.integer("items"), [&](std::int64_t i) {
      std::this_thread::sleep_for(micros);
      sum += i;
    });
    ctx.write_output("out.txt", ctx.string("text") + " " + std::to_string(sum.load()) + "\n");
  }
};

// `throwing`: throws what `what` says: "int" (not a std::exception), "logic" (std::logic_error),
// or nothing ("none": writes out.txt).
class ThrowingStage final : public TestStage {
 public:
  ThrowingStage() : TestStage("throwing", "throws (test stage)") {
    info_.params = {Param::choice("what", {"int", "logic", "none"}, "int").describe("what to throw")};
  }
  void run(StageContext& ctx) const override {
    const std::string what = ctx.string("what");
    if (what == "int") throw 42;
    if (what == "logic") throw std::logic_error("a bug");
    ctx.write_output("out.txt", "fine\n");
  }
};

// Parameters with load-time constraints (a power of two, an increasing list).
class ConstrainedStage final : public TestStage {
 public:
  ConstrainedStage() : TestStage("constrained", "parameters with constraints (test stage)") {
    info_.params = {
        Param::integer("size", 16).range(1, 4096).require_power_of_two().describe("a power of two"),
        Param::real_list("levels", Value::List{}).require_increasing().describe("increasing")};
  }
  void run(StageContext& ctx) const override { ctx.write_output("out.txt", "ok\n"); }
};

inline void register_test_stages(StageRegistry& reg, RunLog* log) {
  reg.add(std::make_unique<TextStage>(log));
  reg.add(std::make_unique<ConcatStage>(log));
  reg.add(std::make_unique<ReadFileStage>(log));
  reg.add(std::make_unique<ReadModelStage>(log));
  reg.add(std::make_unique<MeshOnlyStage>());
  reg.add(std::make_unique<NestedParallelStage>(log));
  reg.add(std::make_unique<ThrowingStage>());
  reg.add(std::make_unique<ConstrainedStage>());
}

}  // namespace sylva::test
