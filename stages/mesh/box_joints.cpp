// Nystad 2010, Appendix D (Connect), §3.3.2, §4.3.3, §5.3.2; Skjermo & Eidheim 2005 (§2.4.1) for
// the backward box. The header lists the cases; this file follows them in the same order.
#include "stages/mesh/box_joints.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace sylva::mesh {
namespace {

using tree::cross;
using tree::dot;
using tree::length;
using tree::normalized;

constexpr double kEqualRadius = 1e-3;  // relative tolerance of the equal-split test
constexpr int kMaxBackwardLevels = 2;  // nested backward boxes before bridging regardless
constexpr double kInsetRatio = 2.5;    // inset a port larger than this many ring sizes ...
constexpr double kInsetSize = 1.6;     // ... to this many ring sizes
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// A face loop of four vertices, counter-clockwise around its outward normal. As a port it is
// replaced by whatever connects there; unused, it is emitted as a face.
using Loop = std::array<std::uint32_t, 4>;

struct Segment {
  std::uint32_t branch = 0;
  std::uint32_t ring = 0;  // first ring of the segment (k + 1 for a continuation, 0 for a child)
  double radius = 0;       // the tree's radius of that ring (ordering and the equal-split test)
};

// Closed square polygon subdivided with the cubic B-spline rule (what Catmull–Clark does to the
// cross-section of a straight, uniformly sampled tube); returns its area for corner distance 1.
double subdivided_square_area(int levels) {
  std::vector<std::array<double, 2>> p;
  for (int j = 0; j < 4; ++j) {
    const double a = std::numbers::pi / 4 + j * std::numbers::pi / 2;
    p.push_back({std::cos(a), std::sin(a)});
  }
  for (int l = 0; l < levels; ++l) {
    std::vector<std::array<double, 2>> q;
    const std::size_t n = p.size();
    for (std::size_t i = 0; i < n; ++i) {
      const auto& a = p[(i + n - 1) % n];
      const auto& b = p[i];
      const auto& c = p[(i + 1) % n];
      q.push_back({(a[0] + 6 * b[0] + c[0]) / 8, (a[1] + 6 * b[1] + c[1]) / 8});
      q.push_back({(b[0] + c[0]) / 2, (b[1] + c[1]) / 2});
    }
    p = std::move(q);
  }
  double area = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& a = p[i];
    const auto& b = p[(i + 1) % p.size()];
    area += a[0] * b[1] - a[1] * b[0];
  }
  return area / 2;
}

class Mesher {
 public:
  Mesher(const MeshSkeleton& sk, const BarkOptions& o, QuadMesh& m, JointStats& st)
      : sk_(sk), o_(o), m_(m), st_(st), repeat_(std::max(1, o.bark_repeat)) {
    ring_base_.resize(sk.branches.size());
    for (std::size_t b = 0; b < sk.branches.size(); ++b)
      ring_base_[b].assign(sk.branches[b].rings.size(), kNone);
  }

  void run() {
    for (std::uint32_t b = 0; b < sk_.branches.size(); ++b) {
      if (sk_.branches[b].parent >= 0) continue;
      ++st_.components;
      const std::uint32_t base = make_ring(b, 0);
      if (!o_.open_base) {
        emit_projected({base + 3, base + 2, base + 1, base}, ring(b, 0).v, FaceKind::kCap);
        ++st_.base_caps;
        base_rings_.push_back(base);  // a crease: the foot stays flat on the ground
      }
      walk_.push_back({b, 0});
      while (!walk_.empty()) {
        const Segment s = walk_.back();
        walk_.pop_back();
        node(s.branch, s.ring);
      }
    }
  }

 private:
  const Ring& ring(std::uint32_t b, std::uint32_t r) const { return sk_.branches[b].rings[r]; }

  std::uint32_t make_ring(std::uint32_t b, std::uint32_t r) {
    const Ring& g = ring(b, r);
    const std::uint32_t base = static_cast<std::uint32_t>(m_.positions.size());
    const double d = o_.corner_scale * g.radius;
    for (int j = 0; j < 4; ++j) {
      const double a = std::numbers::pi / 4 + j * std::numbers::pi / 2;
      m_.positions.push_back(g.center + (g.frame.n * std::cos(a) + g.frame.b * std::sin(a)) * d);
    }
    ring_base_[b][r] = base;
    return base;
  }

  Vec3 p(std::uint32_t v) const { return m_.positions[v]; }
  Vec3 centre(const Loop& l) const { return (p(l[0]) + p(l[1]) + p(l[2]) + p(l[3])) * 0.25; }
  // Newell's normal: robust for non-planar quads.
  Vec3 normal(const Loop& l) const {
    Vec3 n{};
    for (int i = 0; i < 4; ++i) {
      const Vec3 a = p(l[static_cast<std::size_t>(i)]), b = p(l[static_cast<std::size_t>((i + 1) % 4)]);
      n += Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
    }
    return normalized(n);
  }
  double size(const Loop& l) const {
    const Vec3 c = centre(l);
    double s = 0;
    for (std::uint32_t v : l) s += length(p(v) - c);
    return s / 4;
  }
  Vec3 seg_centre(const Segment& s) const { return ring(s.branch, s.ring).center; }

  void emit(const Loop& l, const std::array<Uv, 4>& uv, FaceKind kind) {
    m_.quads.push_back(l);
    m_.uvs.push_back(uv);
    m_.kinds.push_back(kind);
  }

  // Planar projection at the bark's texel density (caps, crotches, backward boxes).
  void emit_projected(const Loop& l, double v_ref, FaceKind kind) {
    const Vec3 c = centre(l), n = normal(l);
    Vec3 e1 = normalized(p(l[1]) - p(l[0]));
    if (length(e1) == 0) e1 = Vec3{1, 0, 0};
    const Vec3 e2 = normalized(cross(n, e1));
    const double scale = repeat_ / sk_.v_unit;
    std::array<Uv, 4> uv;
    for (std::size_t i = 0; i < 4; ++i) {
      const Vec3 d = p(l[i]) - c;
      uv[i] = {static_cast<float>(0.5 + dot(d, e1) * scale),
               static_cast<float>(v_ref * repeat_ + dot(d, e2) * scale)};
    }
    emit(l, uv, kind);
  }

  // Segments at ring k of branch b: the continuation, then the children in tree order.
  std::vector<Segment> segments(std::uint32_t b, std::uint32_t k) const {
    std::vector<Segment> s;
    if (k + 1 < sk_.branches[b].rings.size()) s.push_back({b, k + 1, ring(b, k + 1).source_radius});
    for (std::uint32_t c : sk_.children[b][k]) s.push_back({c, 0, ring(c, 0).source_radius});
    return s;
  }

  void node(std::uint32_t b, std::uint32_t k) {
    const std::uint32_t base = ring_base_[b][k];
    connect({base, base + 1, base + 2, base + 3}, segments(b, k), ring(b, k).v, 0);
  }

  // Appendix D, Connect(Quad, Segments).
  void connect(const Loop& port, std::vector<Segment> segs, double v_base, int level) {
    if (segs.empty()) {
      emit_projected(port, v_base, FaceKind::kCap);  // a tip cap
      ++st_.tip_caps;
      return;
    }
    std::stable_sort(segs.begin(), segs.end(),
                     [](const Segment& a, const Segment& c) { return a.radius > c.radius; });
    if (level < kMaxBackwardLevels && backward(port, segs[0])) {
      backward_box(port, segs, v_base, level);
      return;
    }
    if (segs.size() == 1) {
      const Bridge br = bridge(port, segs[0], v_base);
      for (std::size_t i = 0; i < 4; ++i) emit(br.sides[i], br.side_uv[i], br.kind);
      if (br.inset)
        for (const Loop& l : br.rim) emit_projected(l, v_base, FaceKind::kRim);
      return;
    }
    if (segs[1].radius >= segs[0].radius * (1 - kEqualRadius)) {
      split(port, segs, v_base, level);
      return;
    }
    ordinary(port, segs, v_base, level);
  }

  // The largest segment lies behind the port's plane (more than a twentieth of the port's size:
  // rings that almost touch the port, as at very short segments, bridge fine), or its ring
  // faces away from the port.
  bool backward(const Loop& port, const Segment& s) const {
    const Vec3 n = normal(port);
    const Ring& r = ring(s.branch, s.ring);
    return dot(r.center - centre(port), n) < -0.05 * size(port) || dot(r.frame.t, n) < 0;
  }

  // A smaller copy of `port` (size kInsetSize * ring_size), centred where `target` projects onto
  // the port (kept inside it), and the four rim quads between the two. Returns the copy.
  Loop inset(const Loop& port, Vec3 target, double ring_size, std::array<Loop, 4>& rim) {
    ++st_.insets;
    const Vec3 c = centre(port), n = normal(port);
    Vec3 x = target - n * dot(target - c, n);
    // Keep the homothety centre inside the port so the inset stays inside it.
    auto inside = [&](Vec3 y) {
      for (std::size_t i = 0; i < 4; ++i) {
        const Vec3 a = p(port[i]), b = p(port[(i + 1) % 4]);
        if (dot(y - a, cross(n, b - a)) < 0) return false;
      }
      return true;
    };
    if (!inside(x)) {
      Vec3 lo = c, hi = x;
      for (int it = 0; it < 20; ++it) {
        const Vec3 mid = (lo + hi) * 0.5;
        (inside(mid) ? lo : hi) = mid;
      }
      x = lo;
    }
    x = c + (x - c) * 0.8;  // a margin from the port's edges
    const double ratio = std::min(0.5, kInsetSize * ring_size / size(port));
    Loop inner;
    for (std::size_t i = 0; i < 4; ++i) inner[i] = add_vertex(x + (p(port[i]) - x) * ratio);
    for (std::size_t i = 0; i < 4; ++i) rim[i] = {port[i], port[(i + 1) % 4], inner[(i + 1) % 4], inner[i]};
    return inner;
  }

  struct Bridge {
    std::array<Loop, 4> sides;                 // the four bridge quads (the box's side faces)
    std::array<std::array<Uv, 4>, 4> side_uv;  // their uvs
    FaceKind kind = FaceKind::kTube;           // kTube for a continuation, kJoint for a child
    bool inset = false;                        // the port was inset first:
    std::array<Loop, 4> rim;                   // the four quads around the inset
  };

  // Bridges `port` to the segment's first ring with four quads (returned, not emitted) and
  // schedules the segment's walk. A port much larger than the ring (a twig on a thick branch,
  // common in imported trees) is first inset: a smaller copy of the port, centred where the
  // ring projects onto it, becomes the port, and four rim quads fill the space between.
  Bridge bridge(const Loop& port_in, const Segment& s, double v_base) {
    ++st_.bridges;
    Bridge out;
    out.kind = s.ring > 0 ? FaceKind::kTube : FaceKind::kJoint;
    Loop port = port_in;
    const Ring& g = ring(s.branch, s.ring);
    const double ring_size = o_.corner_scale * g.radius;
    const double port_size = size(port_in);
    if (port_size > kInsetRatio * ring_size) {
      out.inset = true;
      port = inset(port_in, g.center, ring_size, out.rim);
    }
    const std::uint32_t base = make_ring(s.branch, s.ring);
    // The rotation of the ring that best matches the port's corners.
    int shift = 0;
    double best = std::numeric_limits<double>::infinity();
    for (int sh = 0; sh < 4; ++sh) {
      double d = 0;
      for (int i = 0; i < 4; ++i) {
        const Vec3 e =
            p(port[static_cast<std::size_t>(i)]) - p(base + static_cast<std::uint32_t>((i + sh) % 4));
        d += dot(e, e);
      }
      if (d < best) best = d, shift = sh;
    }
    const double v_ring = g.v * repeat_;
    const double v_port = v_base * repeat_;
    for (int i = 0; i < 4; ++i) {
      const int a = (i + shift) % 4;  // ring corner under port corner i
      const std::uint32_t ra = base + static_cast<std::uint32_t>(a);
      const std::uint32_t rb = base + static_cast<std::uint32_t>((a + 1) % 4);
      const double ua = repeat_ * a / 4.0, ub = repeat_ * (a + 1) / 4.0;  // corner 0 is u = 1 after corner 3
      out.sides[static_cast<std::size_t>(i)] = {port[static_cast<std::size_t>(i)],
                                                port[static_cast<std::size_t>((i + 1) % 4)], rb, ra};
      const float fa = static_cast<float>(ua), fb = static_cast<float>(ub);
      const float fp = static_cast<float>(v_port), fr = static_cast<float>(v_ring);
      out.side_uv[static_cast<std::size_t>(i)] = {Uv{fa, fp}, Uv{fb, fp}, Uv{fb, fr}, Uv{fa, fr}};
    }
    walk_.push_back(s);
    return out;
  }

  // Step 4: box between the port and the largest segment; the rest onto its four sides (and,
  // when the port was inset, onto the rim quads around the inset).
  void ordinary(const Loop& port, const std::vector<Segment>& segs, double v_base, int level) {
    ++st_.ordinary_joints;
    const Vec3 box_centre = (centre(port) + seg_centre(segs[0])) * 0.5;
    const Bridge br = bridge(port, segs[0], v_base);
    const std::size_t nfaces = br.inset ? 8 : 4;
    std::array<Loop, 8> faces;
    std::array<Vec3, 8> normals;
    for (std::size_t i = 0; i < 4; ++i) {
      faces[i] = br.sides[i];
      faces[i + 4] = br.rim[i];
    }
    for (std::size_t i = 0; i < nfaces; ++i) normals[i] = normal(faces[i]);
    if (!br.inset)
      for (std::size_t i = 4; i < 8; ++i) normals[i] = Vec3{};  // never chosen over a real face
    std::array<std::vector<Segment>, 8> on_face;
    for (std::size_t j = 1; j < segs.size(); ++j) {
      std::size_t f = best_face(normals, seg_centre(segs[j]) - box_centre);
      if (f >= nfaces) f = 0;
      on_face[f].push_back(segs[j]);
    }
    for (std::size_t i = 0; i < nfaces; ++i) {
      if (on_face[i].empty()) {
        if (i < 4) {
          emit(faces[i], br.side_uv[i], br.kind);
        } else {
          emit_projected(faces[i], v_base, FaceKind::kRim);
        }
      } else {
        if (on_face[i].size() > 1) ++st_.recursive_sides;
        connect(faces[i], on_face[i], v_base, level);
      }
    }
  }

  template <std::size_t N>
  static std::size_t best_face(const std::array<Vec3, N>& normals, Vec3 dir) {
    const Vec3 d = normalized(dir);
    std::size_t best = 0;
    for (std::size_t i = 1; i < N; ++i)
      if (dot(normals[i], d) > dot(normals[best], d)) best = i;
    return best;
  }

  std::uint32_t add_vertex(Vec3 v) {
    m_.positions.push_back(v);
    return static_cast<std::uint32_t>(m_.positions.size() - 1);
  }

  // Step 3: the equal split. The port q0..q3 (rotated so the split runs across edges q1q2 and
  // q3q0) gets a crotch: ridge vertices a1, a2 above the middle of q1q2 and b1, b2 above the
  // middle of q3q0, a little apart along the split direction s. Faces: q1 q2 a2 a1 and
  // q3 q0 b1 b2 (the ends of the ridge) and a1 a2 b2 b1 (the ridge); ports Left = q0 q1 a1 b1
  // (facing +s) and Right = b2 a2 q2 q3 (facing -s).
  void split(const Loop& port, const std::vector<Segment>& segs, double v_base, int level) {
    ++st_.split_joints;
    const Vec3 c = centre(port), n = normal(port);
    const double h = size(port);
    auto in_plane = [&](Vec3 v) { return v - n * dot(v, n); };
    Vec3 axis = in_plane(seg_centre(segs[0]) - seg_centre(segs[1]));
    if (length(axis) < 1e-12 * (h + 1)) axis = in_plane(p(port[0]) + p(port[1]) - p(port[2]) - p(port[3]));
    axis = normalized(axis);
    auto side_dir = [&](const Loop& q) {
      return normalized(in_plane(p(q[0]) + p(q[1]) - p(q[2]) - p(q[3])));
    };
    const Loop rot1 = {port[1], port[2], port[3], port[0]};
    const Loop q = std::abs(dot(side_dir(port), axis)) >= std::abs(dot(side_dir(rot1), axis)) ? port : rot1;
    const Vec3 s = side_dir(q);
    double lift = 0.5 * h;
    for (const Segment& g : segs) lift = std::min(lift, 0.5 * std::max(0.0, dot(seg_centre(g) - c, n)));
    lift = std::max(lift, 0.05 * h);
    const double gap = 0.15 * h;
    const Vec3 m12 = (p(q[1]) + p(q[2])) * 0.5 + n * lift, m30 = (p(q[3]) + p(q[0])) * 0.5 + n * lift;
    const std::uint32_t a1 = add_vertex(m12 + s * gap), a2 = add_vertex(m12 - s * gap);
    const std::uint32_t b1 = add_vertex(m30 + s * gap), b2 = add_vertex(m30 - s * gap);
    emit_projected({q[1], q[2], a2, a1}, v_base, FaceKind::kCrotch);
    emit_projected({q[3], q[0], b1, b2}, v_base, FaceKind::kCrotch);
    emit_projected({a1, a2, b2, b1}, v_base, FaceKind::kCrotch);
    // Sides by direction; never all on one side.
    std::vector<std::pair<double, Segment>> by_side;
    for (const Segment& g : segs) by_side.emplace_back(dot(seg_centre(g) - c, s), g);
    std::vector<Segment> left, right;
    for (const auto& [d, g] : by_side) (d >= 0 ? left : right).push_back(g);
    if (left.empty() || right.empty()) {
      std::stable_sort(by_side.begin(), by_side.end(),
                       [](const auto& x, const auto& y) { return x.first > y.first; });
      left.clear();
      right.clear();
      const std::size_t half = (by_side.size() + 1) / 2;
      for (std::size_t i = 0; i < by_side.size(); ++i) (i < half ? left : right).push_back(by_side[i].second);
    }
    connect({q[0], q[1], a1, b1}, left, v_base, level);
    connect({b2, a2, q[2], q[3]}, right, v_base, level);
  }

  // Step 2 (Skjermo & Eidheim's backward connection): extrude the port into a box and connect
  // every segment to the box face (top or side) that faces it best.
  void backward_box(const Loop& port_in, const std::vector<Segment>& segs, double v_base, int level) {
    ++st_.backward_fallbacks;
    // The box is sized to the largest segment: a large port is inset first.
    Loop port = port_in;
    std::array<Loop, 4> rim;
    const Ring& g0 = ring(segs[0].branch, segs[0].ring);
    const double ring_size = o_.corner_scale * g0.radius;
    const bool inset_first = size(port_in) > kInsetRatio * ring_size;
    if (inset_first) port = inset(port_in, g0.center, ring_size, rim);
    const Vec3 n = normal(port);
    const double h = 0.6 * size(port);
    Loop e;
    for (std::size_t i = 0; i < 4; ++i) e[i] = add_vertex(p(port[i]) + n * h);
    const std::size_t nfaces = inset_first ? 9 : 5;
    std::array<Loop, 9> faces;
    faces[0] = e;
    for (std::size_t i = 0; i < 4; ++i) faces[i + 1] = {port[i], port[(i + 1) % 4], e[(i + 1) % 4], e[i]};
    for (std::size_t i = 0; i < 4; ++i) faces[i + 5] = rim[i];
    std::array<Vec3, 9> normals{};
    for (std::size_t i = 0; i < nfaces; ++i) normals[i] = normal(faces[i]);
    const Vec3 box_centre = centre(port) + n * (0.5 * h);
    std::array<std::vector<Segment>, 9> on_face;
    for (const Segment& g : segs) {
      std::size_t f = best_face(normals, seg_centre(g) - box_centre);
      if (f >= nfaces) f = 0;
      on_face[f].push_back(g);
    }
    for (std::size_t i = 0; i < nfaces; ++i) {
      if (on_face[i].empty()) {
        emit_projected(faces[i], v_base, i < 5 ? FaceKind::kBox : FaceKind::kRim);
      } else {
        connect(faces[i], on_face[i], v_base, level + 1);
      }
    }
  }

  const MeshSkeleton& sk_;
  const BarkOptions& o_;
  QuadMesh& m_;
  JointStats& st_;
  const int repeat_;
  std::vector<Segment> walk_;

 public:
  std::vector<std::vector<std::uint32_t>> ring_base_;  // first vertex of each ring (kNone: none)
  std::vector<std::uint32_t> base_rings_;              // first vertex of every capped base ring
};

}  // namespace

double corner_scale_for_subdivision(int levels) {
  return std::sqrt(std::numbers::pi / subdivided_square_area(std::clamp(levels, 0, 6)));
}

QuadMesh build_bark_mesh(const MeshSkeleton& skeleton, const BarkOptions& options, JointStats* stats,
                         std::vector<std::vector<std::uint32_t>>* ring_vertices) {
  QuadMesh m;
  const std::size_t rings = skeleton.ring_count();
  m.positions.reserve(rings * 4 + 64);
  m.quads.reserve(rings * 4 + 64);
  m.uvs.reserve(rings * 4 + 64);
  m.kinds.reserve(rings * 4 + 64);
  JointStats local;
  Mesher mesher(skeleton, options, m, stats ? *stats : local);
  mesher.run();
  if (ring_vertices) *ring_vertices = mesher.ring_base_;
  if (!mesher.base_rings_.empty()) {
    m.crease.assign(m.positions.size(), 0);
    for (std::uint32_t v : mesher.base_rings_)
      for (std::uint32_t j = 0; j < 4; ++j) m.crease[v + j] = 1;
  }
  return m;
}

}  // namespace sylva::mesh
