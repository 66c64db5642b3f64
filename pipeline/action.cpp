#include "pipeline/action.h"

#include <algorithm>
#include <charconv>
#include <nlohmann/json.hpp>
#include <set>

namespace sylva {

using nlohmann::json;

std::string ActionRecord::key_text() const {
  // Appended piece by piece (no temporaries): a 10,000-node no-op computes 10,000 keys.
  std::string t;
  t.reserve(256);
  auto num = [&](std::uint64_t v) {
    char buf[24];
    auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
    t.append(buf, end);
  };
  t += kActionSalt;
  t += "\nstage ";
  t += stage;
  t += "\nversion ";
  t += std::to_string(version);
  t += '\n';
  for (const auto& [k, v] : params) {
    t += "param ";
    t += k;
    t += '=';
    t += v;
    t += '\n';
  }
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    t += "input ";
    num(i);
    t += ' ';
    t += inputs[i].type;
    t += '\n';
    for (const auto& [name, d] : inputs[i].files) {
      t += "  ";
      t += name;
      t += ' ';
      t += d.hash;
      t += ' ';
      num(d.size);
      t += '\n';
    }
  }
  for (const auto& [k, f] : files) {
    t += "file ";
    t += k;
    t += ' ';
    t += f.digest.hash;
    t += ' ';
    num(f.digest.size);
    t += '\n';
  }
  return t;
}

std::string ActionRecord::key() const { return sha256_hex(key_text()); }

std::string ActionRecord::to_json() const {
  json j;
  j["stage"] = stage;
  j["version"] = version;
  j["params"] = params;
  j["inputs"] = json::array();
  for (const auto& in : inputs) {
    json ji{{"node", in.node}, {"type", in.type}, {"files", json::array()}};
    for (const auto& [n, d] : in.files)
      ji["files"].push_back({{"name", n}, {"hash", d.hash}, {"size", d.size}});
    j["inputs"].push_back(ji);
  }
  j["files"] = json::object();
  for (const auto& [k, f] : files)
    j["files"][k] = {{"path", f.path}, {"hash", f.digest.hash}, {"size", f.digest.size}};
  j["key"] = key();
  return j.dump() + "\n";
}

std::optional<ActionRecord> ActionRecord::from_json(const std::string& text) {
  try {
    json j = json::parse(text);
    ActionRecord r;
    r.stage = j.at("stage").get<std::string>();
    r.version = j.at("version").get<int>();
    r.params = j.at("params").get<std::map<std::string, std::string>>();
    for (const auto& ji : j.at("inputs")) {
      ActionInput in{ji.at("node").get<std::string>(), ji.at("type").get<std::string>(), {}};
      for (const auto& f : ji.at("files"))
        in.files.emplace_back(f.at("name").get<std::string>(),
                              Digest{f.at("hash").get<std::string>(), f.at("size").get<std::uint64_t>()});
      r.inputs.push_back(std::move(in));
    }
    for (const auto& [k, f] : j.at("files").items())
      r.files[k] = {f.at("path").get<std::string>(),
                    Digest{f.at("hash").get<std::string>(), f.at("size").get<std::uint64_t>()}};
    return r;
  } catch (const json::exception&) {
    return std::nullopt;
  }
}

namespace {
std::string short_hash(const std::string& h) { return h.substr(0, 12); }
}  // namespace

std::vector<std::string> explain_difference(const ActionRecord& before, const ActionRecord& now) {
  std::vector<std::string> out;
  if (before.key() == now.key()) return out;
  if (before.stage != now.stage) out.push_back("stage changed: " + before.stage + " -> " + now.stage);
  if (before.version != now.version)
    out.push_back("stage '" + now.stage + "' implementation version changed: " +
                  std::to_string(before.version) + " -> " + std::to_string(now.version));
  std::set<std::string> names;
  for (const auto& [k, v] : before.params) names.insert(k);
  for (const auto& [k, v] : now.params) names.insert(k);
  for (const auto& k : names) {
    if (now.files.count(k) || before.files.count(k)) continue;  // reported as a file below
    auto b = before.params.find(k);
    auto n = now.params.find(k);
    if (b == before.params.end())
      out.push_back("parameter '" + k + "' added: " + n->second);
    else if (n == now.params.end())
      out.push_back("parameter '" + k + "' removed (was " + b->second + ")");
    else if (b->second != n->second)
      out.push_back("parameter '" + k + "' changed: " + b->second + " -> " + n->second);
  }
  if (before.inputs.size() != now.inputs.size())
    out.push_back("number of inputs changed: " + std::to_string(before.inputs.size()) + " -> " +
                  std::to_string(now.inputs.size()));
  for (std::size_t i = 0; i < std::min(before.inputs.size(), now.inputs.size()); ++i) {
    const auto& b = before.inputs[i];
    const auto& n = now.inputs[i];
    if (b.type != n.type || b.files != n.files) {
      std::string what = "input '" + n.node + "' changed";
      if (b.node != n.node)
        what = "input " + std::to_string(i) + " changed: '" + b.node + "' -> '" + n.node + "'";
      for (const auto& [name, d] : n.files) {
        auto it = std::find_if(b.files.begin(), b.files.end(),
                               [&key = name](const auto& x) { return x.first == key; });
        if (it == b.files.end())
          what += "; new file " + name;
        else if (!(it->second == d))
          what += "; " + name + " " + short_hash(it->second.hash) + " -> " + short_hash(d.hash);
      }
      for (const auto& [name, d] : b.files)
        if (std::none_of(n.files.begin(), n.files.end(),
                         [&key = name](const auto& x) { return x.first == key; }))
          what += "; file " + name + " gone";
      out.push_back(what);
    }
  }
  for (const auto& [k, f] : now.files) {
    auto b = before.files.find(k);
    if (b == before.files.end())
      out.push_back("file parameter '" + k + "' added: " + f.path);
    else if (!(b->second.digest == f.digest))
      out.push_back("file '" + f.path + "' (parameter '" + k +
                    "') changed: " + short_hash(b->second.digest.hash) + " -> " + short_hash(f.digest.hash) +
                    (b->second.path != f.path ? " (was " + b->second.path + ")" : ""));
  }
  for (const auto& [k, f] : before.files)
    if (!now.files.count(k)) out.push_back("file parameter '" + k + "' removed (was " + f.path + ")");
  if (out.empty()) out.push_back("action key changed (salt or encoding)");
  return out;
}

}  // namespace sylva
