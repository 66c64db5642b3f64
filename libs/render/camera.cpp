// Camera sets: YAML parsing with yaml-cpp (keeping each node's mark for messages), validation
// that collects every problem before failing (and reports keys that were never read, so a
// misspelled key is an error, not a silent default), and view resolution.
#include "libs/render/camera.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include "libs/fileio/read_file.h"

namespace sylva::render {
namespace {

constexpr float kPi = 3.14159265358979323846f;
float radians(float deg) { return deg * kPi / 180.f; }

std::string join_lines(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) {
    if (!s.empty()) s += '\n';
    s += l;
  }
  return s;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

// "; did you mean 'x'?" for the closest candidate, or for a candidate that is the word plus a
// unit suffix ('azimuth' -> 'azimuth_deg'); "" when nothing is close.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  for (const auto& c : candidates)
    if (c.size() > word.size() + 1 && c.compare(0, word.size(), word) == 0 && c[word.size()] == '_')
      return "; did you mean '" + c + "'?";
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best.empty() ? std::string() : "; did you mean '" + best + "'?";
}

// Parses one file, collecting errors at node positions.
class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  void error(const YAML::Mark& mark, const std::string& msg) {
    std::string loc = source_;
    if (mark.line >= 0) loc += ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
    errors_.push_back(loc + ": error: " + msg);
  }
  const std::vector<std::string>& errors() const { return errors_; }

  // A map whose keys are checked against `allowed` (unknown keys are errors).
  bool check_map(const YAML::Node& node, const std::string& what, const std::vector<std::string>& allowed) {
    if (!node.IsMap()) {
      error(node.Mark(), what + " must be a mapping");
      return false;
    }
    for (const auto& kv : node) {
      const std::string key = kv.first.as<std::string>("");
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
        error(kv.first.Mark(), "unknown key '" + key + "' in " + what + did_you_mean(key, allowed));
    }
    return true;
  }

  std::optional<double> number(const YAML::Node& map, const std::string& key, const std::string& what) {
    const YAML::Node n = map[key];
    if (!n) return std::nullopt;
    double v = 0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v)) {
      error(n.Mark(), "'" + key + "' in " + what + " must be a number");
      return std::nullopt;
    }
    return v;
  }

  std::optional<int> integer(const YAML::Node& map, const std::string& key, const std::string& what) {
    const YAML::Node n = map[key];
    if (!n) return std::nullopt;
    long long v = 0;
    if (!n.IsScalar() || !YAML::convert<long long>::decode(n, v) || v < -(1LL << 30) || v > (1LL << 30)) {
      error(n.Mark(), "'" + key + "' in " + what + " must be an integer");
      return std::nullopt;
    }
    return int(v);
  }

  std::optional<Eigen::Vector3d> vec3(const YAML::Node& map, const std::string& key,
                                      const std::string& what) {
    const YAML::Node n = map[key];
    if (!n) return std::nullopt;
    Eigen::Vector3d v;
    bool ok = n.IsSequence() && n.size() == 3;
    for (std::size_t i = 0; ok && i < 3; ++i) {
      double d = 0;
      ok = n[i].IsScalar() && YAML::convert<double>::decode(n[i], d) && std::isfinite(d);
      v[int(i)] = d;
    }
    if (!ok) {
      error(n.Mark(), "'" + key + "' in " + what + " must be a list of three numbers [x, y, z]");
      return std::nullopt;
    }
    return v;
  }

  CameraSet parse(const YAML::Node& root) {
    CameraSet set;
    set.source = source_;
    const std::string top = "camera set";
    if (!root || root.IsNull()) {
      error(YAML::Mark(), "camera set is empty");
      return set;
    }
    if (!check_map(root, top, {"version", "width", "height", "msaa", "supersample", "fov_y_deg", "views"}))
      return set;

    const auto version = integer(root, "version", top);
    if (!root["version"]) {
      error(root.Mark(), "missing key 'version' (must be 1)");
    } else if (version && *version != 1) {
      error(root["version"].Mark(),
            "unsupported camera set version " + std::to_string(*version) + " (must be 1)");
    }
    auto size = [&](const char* key, int& dst) {
      if (!root[key]) {
        error(root.Mark(), std::string("missing key '") + key + "'");
      } else if (auto v = integer(root, key, top)) {
        if (*v < 1 || *v > 16384) {
          error(root[key].Mark(),
                std::string("'") + key + "' must be between 1 and 16384, got " + std::to_string(*v));
        } else {
          dst = *v;
        }
      }
    };
    size("width", set.width);
    size("height", set.height);
    if (auto v = integer(root, "msaa", top)) {
      if (*v != 1 && *v != 2 && *v != 4 && *v != 8 && *v != 16) {
        error(root["msaa"].Mark(), "'msaa' must be 1 (off), 2, 4, 8 or 16, got " + std::to_string(*v));
      } else {
        set.msaa = *v;
      }
    }
    if (auto v = integer(root, "supersample", top)) {
      if (*v < 1 || *v > 4) {
        error(root["supersample"].Mark(),
              "'supersample' must be 1 (off), 2, 3 or 4, got " + std::to_string(*v));
      } else {
        set.supersample = *v;
      }
    }
    if (auto v = fov(root, top)) set.fov_y_deg = *v;
    const float default_fov = float(set.fov_y_deg);

    const YAML::Node views = root["views"];
    if (!views) {
      error(root.Mark(), "missing key 'views'");
      return set;
    }
    if (!views.IsSequence() || views.size() == 0) {
      error(views.Mark(), "'views' must be a non-empty list");
      return set;
    }
    std::set<std::string> names;
    for (std::size_t i = 0; i < views.size(); ++i) {
      if (auto v = parse_view(views[i], i, default_fov)) {
        if (!names.insert(v->name).second) {
          error(views[i]["name"].Mark(), "duplicate view name '" + v->name + "'");
        } else {
          set.views.push_back(std::move(*v));
        }
      }
    }
    return set;
  }

 private:
  std::optional<double> fov(const YAML::Node& map, const std::string& what) {
    auto v = number(map, "fov_y_deg", what);
    if (!v) return std::nullopt;
    if (*v <= 0 || *v >= 180) {
      error(map["fov_y_deg"].Mark(), "'fov_y_deg' must be between 0 and 180 degrees (exclusive)");
      return std::nullopt;
    }
    return *v;
  }

  std::optional<CameraView> parse_view(const YAML::Node& node, std::size_t index, float default_fov) {
    std::string what = "view " + std::to_string(index + 1);
    if (!check_map(node, what, {"name", "orbit", "eye", "target", "up", "fov_y_deg"})) return std::nullopt;
    CameraView view;
    bool ok = true;
    const YAML::Node name = node["name"];
    static const std::regex kName("[A-Za-z0-9_.-]+");
    if (!name) {
      error(node.Mark(), "missing key 'name' in " + what);
      ok = false;
    } else if (!name.IsScalar() || !std::regex_match(name.Scalar(), kName)) {
      error(name.Mark(), "view name must match [A-Za-z0-9_.-]+");
      ok = false;
    } else {
      view.name = name.Scalar();
      what = "view '" + view.name + "'";
    }
    view.fov_y_deg = default_fov;
    if (node["fov_y_deg"]) {
      if (auto v = fov(node, what)) {
        view.fov_y_deg = float(*v);
      } else {
        ok = false;
      }
    }

    const bool orbit = bool(node["orbit"]);
    const bool look = node["eye"] || node["target"] || node["up"];
    if (orbit && look) {
      error(node["orbit"].Mark(), what + " has both 'orbit' and 'eye'/'target'; use one");
      return std::nullopt;
    }
    if (orbit) {
      const std::optional<OrbitView> ov = parse_orbit(node["orbit"], what, ok);
      if (!ov) return std::nullopt;
      view.placement = *ov;
    } else if (look) {
      const std::optional<LookAtView> lv = parse_look_at(node, what, ok);
      if (!lv) return std::nullopt;
      view.placement = *lv;
    } else {
      error(node.Mark(), what + " needs either 'orbit' or 'eye' and 'target'");
      return std::nullopt;
    }
    if (!ok) return std::nullopt;
    return view;
  }

  // A view's `orbit` map `o` (`what` names the view); `ok` turns false on a value out of range.
  // nullopt after an error that leaves no orbit to check further.
  std::optional<OrbitView> parse_orbit(const YAML::Node& o, const std::string& what, bool& ok) {
    const std::string owhat = "orbit of " + what;
    if (!check_map(o, owhat, {"azimuth_deg", "elevation_deg", "distance_factor", "distance_m"}))
      return std::nullopt;
    OrbitView ov;
    if (auto v = number(o, "azimuth_deg", owhat)) ov.azimuth_deg = float(*v);
    if (auto v = number(o, "elevation_deg", owhat)) {
      if (*v < -90 || *v > 90) {
        error(o["elevation_deg"].Mark(), "'elevation_deg' must be between -90 and 90");
        ok = false;
      }
      ov.elevation_deg = float(*v);
    }
    if (o["distance_factor"] && o["distance_m"]) {
      error(o["distance_m"].Mark(), owhat + " has both 'distance_factor' and 'distance_m'; use one");
      ok = false;
    }
    if (auto v = number(o, "distance_factor", owhat)) {
      if (*v <= 0) {
        error(o["distance_factor"].Mark(), "'distance_factor' must be positive");
        ok = false;
      }
      ov.distance_factor = float(*v);
    }
    if (auto v = number(o, "distance_m", owhat)) {
      if (*v <= 0) {
        error(o["distance_m"].Mark(), "'distance_m' must be positive");
        ok = false;
      }
      ov.distance_m = float(*v);
    }
    return ov;
  }

  // A view's eye, target and up (`what` names the view); `ok` turns false on a degenerate view.
  // nullopt when eye or target is missing or a vector does not parse.
  std::optional<LookAtView> parse_look_at(const YAML::Node& node, const std::string& what, bool& ok) {
    LookAtView lv;
    const auto eye = vec3(node, "eye", what);
    const auto target = vec3(node, "target", what);
    const auto up = vec3(node, "up", what);
    if (!node["eye"]) error(node.Mark(), what + " has 'target' but no 'eye'");
    if (!node["target"]) error(node.Mark(), what + " has 'eye' but no 'target'");
    if (!eye || !target || (node["up"] && !up)) return std::nullopt;
    lv.eye = *eye;
    lv.target = *target;
    if (up) lv.up = *up;
    // Judged as the renderer will see the view: in floats.
    const Vec3 dir = lv.target.cast<float>() - lv.eye.cast<float>();
    const Vec3 up_f = lv.up.cast<float>();
    if (dir.norm() < 1e-6f) {
      error(node["eye"].Mark(), what + ": 'eye' and 'target' are the same point");
      ok = false;
    } else if (up_f.norm() < 1e-6f || dir.normalized().cross(up_f.normalized()).norm() < 1e-4f) {
      error((node["up"] ? node["up"] : node["eye"]).Mark(),
            what + ": 'up' is parallel to the viewing direction");
      ok = false;
    }
    return lv;
  }

  std::string source_;
  std::vector<std::string> errors_;
};

}  // namespace

CameraSetError::CameraSetError(std::vector<std::string> errors)
    : std::runtime_error(join_lines(errors)), errors_(std::move(errors)) {}

CameraSet parse_camera_set(std::string_view yaml_text, const std::string& source_name) {
  Parser parser(source_name);
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::ParserException& e) {
    parser.error(e.mark, e.msg);
    throw CameraSetError(parser.errors());
  }
  CameraSet set = parser.parse(root);
  if (!parser.errors().empty()) throw CameraSetError(parser.errors());
  return set;
}

CameraSet load_camera_set(const std::filesystem::path& path) {
  std::string text;
  try {
    text = fileio::read_file(path);
  } catch (const fileio::FileReadError& e) {
    throw CameraSetError({e.what()});
  }
  return parse_camera_set(text, path.string());
}

namespace {

// "[x, y, z]" in metres with 4 decimals (0.1 mm), however large.
std::string position(const Eigen::Vector3d& v) {
  const char* format = "[%.4f, %.4f, %.4f]";
  std::string out(std::size_t(std::snprintf(nullptr, 0, format, v.x(), v.y(), v.z())), '\0');
  std::snprintf(out.data(), out.size() + 1, format, v.x(), v.y(), v.z());
  return out;
}

std::string number(const char* format, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}

}  // namespace

std::string write_camera_set(const CameraSet& set, std::string_view comment) {
  std::string y;
  while (!comment.empty()) {
    const std::size_t end = std::min(comment.find('\n'), comment.size());
    y += "# " + std::string(comment.substr(0, end)) + "\n";
    comment.remove_prefix(std::min(end + 1, comment.size()));
  }
  y += "version: 1\nwidth: " + std::to_string(set.width) + "\nheight: " + std::to_string(set.height) +
       "\nmsaa: " + std::to_string(set.msaa) + "\n";
  if (set.supersample > 1) y += "supersample: " + std::to_string(set.supersample) + "\n";
  y += "fov_y_deg: " + number("%.6g", set.fov_y_deg) + "\n";
  y += "views:\n";
  for (const CameraView& v : set.views) {
    y += "  - name: " + v.name + "\n";
    if (const auto* o = std::get_if<OrbitView>(&v.placement)) {
      y += "    orbit: { azimuth_deg: " + number("%.9g", o->azimuth_deg) +
           ", elevation_deg: " + number("%.9g", o->elevation_deg) +
           (o->distance_m > 0 ? ", distance_m: " + number("%.9g", o->distance_m)
                              : ", distance_factor: " + number("%.9g", o->distance_factor)) +
           " }\n";
    } else {
      const auto& l = std::get<LookAtView>(v.placement);
      y += "    eye: " + position(l.eye) + "\n    target: " + position(l.target) + "\n";
      if (l.up != Eigen::Vector3d::UnitY()) y += "    up: " + position(l.up) + "\n";
    }
    if (v.fov_y_deg != float(set.fov_y_deg)) y += "    fov_y_deg: " + number("%.9g", v.fov_y_deg) + "\n";
  }
  return y;
}

Mat4 Camera::view_matrix() const {
  const Vec3 f = (target - eye).normalized();
  const Vec3 s = f.cross(up).normalized();
  const Vec3 u = s.cross(f);
  Mat4 m = Mat4::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Mat4 Camera::projection_matrix(float aspect) const {
  const float t = 1.f / std::tan(radians(fov_y_deg) * 0.5f);
  Mat4 m = Mat4::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (z_far + z_near) / (z_near - z_far);
  m(2, 3) = 2.f * z_far * z_near / (z_near - z_far);
  m(3, 2) = -1.f;
  return m;
}

Camera resolve(const CameraView& view, const Bounds& scene_bounds, float aspect) {
  Bounds b = scene_bounds;
  if (b.empty()) {
    b.extend(Vec3(-0.5f, -0.5f, -0.5f));
    b.extend(Vec3(0.5f, 0.5f, 0.5f));
  }
  const Vec3 center = b.center();
  const float radius = std::max(b.radius(), 1e-3f);

  Camera cam;
  cam.name = view.name;
  cam.fov_y_deg = view.fov_y_deg;
  if (const auto* o = std::get_if<OrbitView>(&view.placement)) {
    const float az = radians(o->azimuth_deg), el = radians(o->elevation_deg);
    const Vec3 dir(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
    // The sphere fits when its angular radius equals the narrower half field of view.
    const float half_y = radians(view.fov_y_deg) * 0.5f;
    const float half_x = std::atan(std::tan(half_y) * aspect);
    const float fit = radius / std::sin(std::min(half_y, half_x));
    const float distance = o->distance_m > 0 ? o->distance_m : o->distance_factor * fit;
    cam.target = center;
    cam.eye = center + dir * distance;
    cam.up = Vec3::UnitY();
    if (std::abs(dir.y()) > 0.9999f) {
      // Straight above or below: keep the image's top toward where +Y pointed when orbiting over.
      const Vec3 horizontal(std::sin(az), 0.f, std::cos(az));
      cam.up = dir.y() > 0 ? Vec3(-horizontal) : horizontal;
    }
  } else {
    const auto& l = std::get<LookAtView>(view.placement);
    cam.eye = l.eye.cast<float>();
    cam.target = l.target.cast<float>();
    cam.up = l.up.cast<float>();
  }
  const float d = (cam.eye - center).norm();
  cam.z_far = d + radius * 1.05f;
  cam.z_near = std::max(d - radius * 1.05f, cam.z_far * 1e-4f);
  return cam;
}

}  // namespace sylva::render
