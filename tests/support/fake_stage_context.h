// A StageContext for running one stage's adapter in a test: the stage's defaults plus overrides
// as parameters, inputs from directories (one artifact per directory, every file in it), outputs
// written into a directory, no file parameters, seed 0. Header-only: a test that includes it links
// sylva_stage_api (through its stage) and sylva_test_support.
#pragma once

#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "pipeline/stage.h"
#include "tests/support/test_support.h"

namespace sylva::test {

class FakeStageContext final : public StageContext {
 public:
  struct Input {
    std::string node, type;
    std::filesystem::path dir;
  };

  FakeStageContext(const Stage& stage, const std::vector<Input>& inputs, std::filesystem::path out,
                   const Value::Object& overrides = {})
      : out_(std::move(out)) {
    for (const ParamSpec& p : stage.info().params)
      if (!p.required()) params_[p.name] = p.default_value;
    for (const auto& [k, v] : overrides) params_[k] = v;
    for (const Input& i : inputs) {
      InputArtifact in;
      in.node = i.node;
      in.type = i.type;
      std::set<std::string> names;
      for (const auto& e : std::filesystem::directory_iterator(i.dir))
        names.insert(e.path().filename().string());
      for (const auto& n : names) in.files.push_back({n, i.dir / n, "0"});
      inputs_.push_back(std::move(in));
    }
  }
  const std::string& node_name() const override { return name_; }
  const Value::Object& params() const override { return params_; }
  const std::vector<InputArtifact>& inputs() const override { return inputs_; }
  std::filesystem::path param_file(std::string_view) const override {
    throw std::logic_error("no file parameters");
  }
  Rng rng(std::string_view stream) const override { return Rng(0, stream); }
  const std::filesystem::path& scratch_dir() const override { return out_; }
  std::filesystem::path output_path(std::string_view name) override {
    declared.insert(std::string(name));
    return out_ / std::string(name);
  }
  void write_output(std::string_view name, std::string_view bytes) override {
    write_file(output_path(name), std::string(bytes));
  }
  void check_cancelled() const override {}

  std::set<std::string> declared;  // every output the stage declared

 private:
  std::string name_ = "node";
  Value::Object params_;
  std::vector<InputArtifact> inputs_;
  std::filesystem::path out_;
};

}  // namespace sylva::test
