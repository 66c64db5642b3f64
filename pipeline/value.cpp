#include "pipeline/value.h"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace sylva {

std::string json_quote(std::string_view s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  out += '"';
  return out;
}

std::string format_real(double d) {
  if (!std::isfinite(d)) return std::isnan(d) ? "nan" : (d > 0 ? "inf" : "-inf");
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, d);
  std::string s(buf, end);
  // Keep reals distinguishable from integers in canonical text.
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string Value::canonical() const {
  struct V {
    std::string operator()(std::monostate) const { return "null"; }
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(double d) const { return format_real(d); }
    std::string operator()(const std::string& s) const { return json_quote(s); }
    std::string operator()(const List& l) const {
      std::string out = "[";
      for (std::size_t i = 0; i < l.size(); ++i) out += (i ? "," : "") + l[i].canonical();
      return out + "]";
    }
    std::string operator()(const Object& o) const {
      std::string out = "{";
      bool first = true;
      for (const auto& [k, v] : o) {
        out += (first ? "" : ",") + json_quote(k) + ":" + v.canonical();
        first = false;
      }
      return out + "}";
    }
  };
  return std::visit(V{}, v_);
}

}  // namespace sylva
