// Runs tools/validate_gltf.mjs in a child process (posix_spawnp, no shell: file names need no
// quoting) and parses its per-file summary lines; see gltf_validator.h.
#include "tests/support/gltf_validator.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string_view>

extern char** environ;

namespace sylva::test {
namespace {

namespace fs = std::filesystem;

// tools/validate_gltf.mjs from $SYLVA_SOURCE_DIR, the working directory or a parent of it.
fs::path find_script() {
  const fs::path rel = fs::path("tools") / "validate_gltf.mjs";
  if (const char* src = std::getenv("SYLVA_SOURCE_DIR"); src && *src) {
    if (fs::exists(fs::path(src) / rel)) return fs::path(src) / rel;
  }
  std::error_code ec;
  fs::path dir = fs::current_path(ec);
  for (int i = 0; i < 6 && !dir.empty(); ++i) {
    if (fs::exists(dir / rel, ec)) return dir / rel;
    if (dir == dir.parent_path()) break;
    dir = dir.parent_path();
  }
  return {};
}

bool validator_required() {
  const char* v = std::getenv("SYLVA_REQUIRE_GLTF_VALIDATOR");
  return v && *v && std::string_view(v) != "0";
}

struct RunResult {
  bool spawned = false;
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

RunResult run(const std::vector<std::string>& argv) {
  RunResult r;
  int fds[2];
  if (pipe(fds) != 0) return r;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  if (rc != 0) {
    close(fds[0]);
    return r;
  }
  r.spawned = true;
  char buf[4096];
  for (;;) {
    const ssize_t n = read(fds[0], buf, sizeof buf);
    if (n > 0) {
      r.output.append(buf, static_cast<std::size_t>(n));
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      break;
    }
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// "N errors, M warnings" -> true and the two numbers.
bool parse_counts(std::string_view s, int& errors, int& warnings) {
  char* end = nullptr;
  const std::string text(s);
  const long e = std::strtol(text.c_str(), &end, 10);
  if (end == text.c_str() || std::strncmp(end, " errors, ", 9) != 0) return false;
  const char* w_begin = end + 9;
  const long w = std::strtol(w_begin, &end, 10);
  if (end == w_begin || std::strcmp(end, " warnings") != 0) return false;
  errors = static_cast<int>(e);
  warnings = static_cast<int>(w);
  return true;
}

std::vector<ValidationResult> all_with(const std::vector<fs::path>& files, bool skipped,
                                       const std::string& why) {
  std::vector<ValidationResult> out(files.size());
  for (std::size_t i = 0; i < files.size(); ++i) {
    out[i].file = files[i];
    if (skipped) {
      out[i].skipped = true;
      out[i].skip_reason = why;
    } else {
      out[i].tool_error = why;
    }
  }
  return out;
}

}  // namespace

std::vector<ValidationResult> validate_gltf(const std::vector<fs::path>& files) {
  if (files.empty()) return {};
  const bool required = validator_required();
  const fs::path script = find_script();
  if (script.empty())
    return all_with(files, !required, "tools/validate_gltf.mjs not found (run the test from the repository)");
  std::vector<std::string> argv = {"node", script.string(), "--max-warnings", "50"};
  for (const auto& f : files) argv.push_back(f.string());
  const RunResult r = run(argv);
  if (!r.spawned || r.exit_code == 127) return all_with(files, !required, "node is not installed");
  if (r.exit_code == 3)
    return all_with(files, !required, "gltf-validator is not installed (run tools/setup.sh)");

  // One summary line per file, in order, each followed by indented issue lines.
  std::vector<ValidationResult> out(files.size());
  for (std::size_t i = 0; i < files.size(); ++i) out[i].file = files[i];
  std::size_t current = files.size();
  std::size_t next = 0;
  std::size_t pos = 0;
  while (pos < r.output.size()) {
    std::size_t eol = r.output.find('\n', pos);
    if (eol == std::string::npos) eol = r.output.size();
    const std::string_view line(r.output.data() + pos, eol - pos);
    pos = eol + 1;
    if (line.starts_with("  ")) {
      if (current < out.size()) {
        out[current].report += std::string(line) + "\n";
        const std::string_view text = line.substr(2);
        if (text.starts_with("error ") || text.starts_with("warning "))
          out[current].messages.emplace_back(text);
      }
      continue;
    }
    const std::string prefix = next < files.size() ? files[next].string() + ": " : std::string();
    if (!prefix.empty() && line.starts_with(prefix)) {
      current = next++;
      out[current].report += std::string(line) + "\n";
      const std::string_view rest = line.substr(prefix.size());
      if (!parse_counts(rest, out[current].errors, out[current].warnings))
        out[current].tool_error = std::string(rest);
    } else if (current < out.size()) {
      out[current].report += std::string(line) + "\n";
    }
  }
  for (std::size_t i = next; i < out.size(); ++i)
    out[i].tool_error =
        "no result from the validator (exit code " + std::to_string(r.exit_code) + "): " + r.output;
  return out;
}

ValidationResult validate_gltf(const fs::path& file) {
  return validate_gltf(std::vector<fs::path>{file}).front();
}

}  // namespace sylva::test
