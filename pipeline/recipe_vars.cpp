// Substitution works on RawNode trees, not on YAML text, so every substituted value keeps the
// file:line:col of the scalar it came from and errors in an expansion point at the template.
#include "pipeline/recipe_vars.h"

#include <algorithm>
#include <cctype>

namespace sylva {
namespace {

// Variable references in `text` ("$${" is a literal "${"). Unterminated "${" is reported.
std::vector<std::string> vars_in(const std::string& text, bool* malformed) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i + 1 < text.size(); ++i) {
    if (text[i] == '$' && text[i + 1] == '$') {
      ++i;
      continue;
    }
    if (text[i] == '$' && text[i + 1] == '{') {
      const auto end = text.find('}', i + 2);
      if (end == std::string::npos) {
        *malformed = true;
        return out;
      }
      out.push_back(text.substr(i + 2, end - i - 2));
      i = end;
    }
  }
  return out;
}

std::string substitute_text(const std::string& text, const std::map<std::string, std::string>& vars) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '$' && i + 1 < text.size() && text[i + 1] == '$') {
      out += '$';
      ++i;
    } else if (text[i] == '$' && i + 1 < text.size() && text[i + 1] == '{') {
      const auto end = text.find('}', i + 2);
      out += vars.at(text.substr(i + 2, end - i - 2));
      i = end;
    } else {
      out += text[i];
    }
  }
  return out;
}

}  // namespace

void collect_vars(const RawNode& n, std::vector<VarRef>& out, const SourceFiles& src, Diagnostics& diags,
                  bool* dollar) {
  if (n.is_scalar() && n.text.find('$') != std::string::npos) {
    *dollar = true;
    bool malformed = false;
    for (auto& v : vars_in(n.text, &malformed)) {
      const bool ident = !v.empty() && std::all_of(v.begin(), v.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
      });
      if (!ident) src.error(diags, n.loc, "invalid variable name '${" + v + "}' in '" + n.text + "'");
      out.push_back({v, n.loc});
    }
    if (malformed) src.error(diags, n.loc, "unterminated '${' in '" + n.text + "'");
  }
  for (const auto& i : n.items) collect_vars(i, out, src, diags, dollar);
  for (const auto& [k, v] : n.entries) {
    collect_vars(k, out, src, diags, dollar);
    collect_vars(v, out, src, diags, dollar);
  }
}

RawNode substitute_vars(const RawNode& n, const std::map<std::string, std::string>& vars) {
  RawNode r = n;
  if (r.is_scalar()) r.text = substitute_text(r.text, vars);
  for (auto& i : r.items) i = substitute_vars(i, vars);
  for (auto& [k, v] : r.entries) {
    k = substitute_vars(k, vars);
    v = substitute_vars(v, vars);
  }
  return r;
}

}  // namespace sylva
