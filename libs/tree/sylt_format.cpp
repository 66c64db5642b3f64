// .sylt encoder and defensive decoder; the layout is specified in docs/tree-format.md and the
// two functions below follow it field by field in the same order.
#include "libs/tree/sylt_format.h"

#include <bit>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <type_traits>

#include "libs/fileio/read_file.h"

namespace sylva::tree {

namespace {

constexpr std::size_t kHeaderSize = 16;  // magic(8) version(4) flags(4)
constexpr std::size_t kChecksumSize = 8;
constexpr std::size_t kMaxString = kMaxTextBytes;  // the writer refuses longer (validate_tree)
constexpr std::size_t kBranchHeader = 4 + 4 + 8 + 4 + 4;
constexpr std::size_t kNodeSize = 4 * 8;
constexpr std::size_t kLeafSize = 4 + 9 * 4 + 2 * 4 + 1;
constexpr std::size_t kNeedleSize = 4 + 6 * 4 + 4;
// Version 3's source geometry: the smallest record of each kind (empty names and arrays).
constexpr std::size_t kPrimitiveHeader = 4 + 4 + 1 + 4 + 4;  // name, material, attributes, 2 counts
constexpr std::size_t kMaterialSize = 4 + 4 * 4 + 4 + 1 + 4 + 1 + 4 + 4;
constexpr std::size_t kImageHeader = 4 + 4 + 4;  // name, mime type, byte count
constexpr std::uint8_t kHasNormals = 1, kHasUvs = 2;

template <class U>
U to_little(U v) {
  if constexpr (std::endian::native == std::endian::little) {
    return v;
  } else {
    U r = 0;
    for (std::size_t i = 0; i < sizeof(U); ++i) r = static_cast<U>((r << 8) | ((v >> (8 * i)) & 0xff));
    return r;
  }
}

template <class T>
auto bits_of(T v) {
  if constexpr (sizeof(T) == 8)
    return std::bit_cast<std::uint64_t>(v);
  else if constexpr (sizeof(T) == 4)
    return std::bit_cast<std::uint32_t>(v);
  else if constexpr (sizeof(T) == 1)
    return std::bit_cast<std::uint8_t>(v);
}

class Writer {
 public:
  template <class T>
  void put(T v) {
    static_assert(std::is_arithmetic_v<T>);
    const auto u = to_little(bits_of(v));
    char buf[sizeof u];
    std::memcpy(buf, &u, sizeof u);
    out.append(buf, sizeof u);
  }
  void put(Vec3 v) {
    put(v.x);
    put(v.y);
    put(v.z);
  }
  void put(Vec3f v) {
    put(v.x);
    put(v.y);
    put(v.z);
  }
  void put(Color c) {
    put(c.r);
    put(c.g);
    put(c.b);
  }
  void put(const std::string& s) {
    put(static_cast<std::uint32_t>(s.size()));
    out += s;
  }
  std::string out;
};

class Reader {
 public:
  Reader(std::string_view bytes, std::string_view source) : b_(bytes), src_(source) {}

  [[noreturn]] void fail(const std::string& what) const { fail_at(pos_, what); }
  [[noreturn]] void fail_at(std::size_t offset, const std::string& what) const {
    throw TreeFormatError(std::string(src_) + ": byte " + std::to_string(offset) + ": " + what);
  }
  std::size_t left() const { return b_.size() - pos_; }
  void need(std::size_t n, const char* what) const {
    if (left() < n)
      fail(std::string("truncated: ") + what + " needs " + std::to_string(n) + " bytes, " +
           std::to_string(left()) + " left");
  }
  template <class T>
  T get(const char* what) {
    need(sizeof(T), what);
    decltype(bits_of(T{})) u;
    std::memcpy(&u, b_.data() + pos_, sizeof u);
    pos_ += sizeof u;
    return std::bit_cast<T>(to_little(u));
  }
  Vec3 vec3(const char* what) {
    need(24, what);
    Vec3 v;
    v.x = get<double>(what);
    v.y = get<double>(what);
    v.z = get<double>(what);
    return v;
  }
  Vec3f vec3f(const char* what) {
    need(12, what);
    Vec3f v;
    v.x = get<float>(what);
    v.y = get<float>(what);
    v.z = get<float>(what);
    return v;
  }
  Color color(const char* what) {
    need(12, what);
    Color c;
    c.r = get<float>(what);
    c.g = get<float>(what);
    c.b = get<float>(what);
    return c;
  }
  std::string string(const char* what, std::size_t max = kMaxString) {
    const auto n = get<std::uint32_t>(what);
    if (n > max)
      fail_at(pos_ - 4,
              std::string(what) + " length " + std::to_string(n) + " exceeds " + std::to_string(max));
    need(n, what);
    std::string s(b_.substr(pos_, n));
    pos_ += n;
    return s;
  }
  // A record count, checked against the bytes left so a corrupt count cannot allocate wildly.
  std::uint32_t count(std::size_t record_size, const char* what) {
    const std::size_t at = pos_;
    const auto n = get<std::uint32_t>(what);
    if (static_cast<std::uint64_t>(n) * record_size > left())
      fail_at(at, std::string(what) + " " + std::to_string(n) + " needs " +
                      std::to_string(static_cast<std::uint64_t>(n) * record_size) + " bytes, " +
                      std::to_string(left()) + " left");
    return n;
  }
  std::size_t pos() const { return pos_; }

 private:
  std::string_view b_;
  std::string_view src_;
  std::size_t pos_ = 0;
};

}  // namespace

std::uint64_t fnv1a64(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

namespace {

// Version 3's last section: the imported mesh, arrays written whole (bit patterns, no rounding).
void put_source(Writer& w, const SourceGeometry& g) {
  w.put(static_cast<std::uint32_t>(g.primitives.size()));
  for (const SourcePrimitive& p : g.primitives) {
    w.put(p.name);
    w.put(p.material);
    w.put(static_cast<std::uint8_t>((p.normals.empty() ? 0 : kHasNormals) | (p.uvs.empty() ? 0 : kHasUvs)));
    w.put(static_cast<std::uint32_t>(p.positions.size()));
    for (Vec3f v : p.positions) w.put(v);
    for (Vec3f v : p.normals) w.put(v);
    for (const auto& uv : p.uvs) {
      w.put(uv[0]);
      w.put(uv[1]);
    }
    w.put(static_cast<std::uint32_t>(p.indices.size()));
    for (std::uint32_t i : p.indices) w.put(i);
  }
  w.put(static_cast<std::uint32_t>(g.materials.size()));
  for (const SourceMaterial& m : g.materials) {
    w.put(m.name);
    for (float c : m.base_color) w.put(c);
    w.put(m.base_color_image);
    w.put(static_cast<std::uint8_t>(m.alpha_mode));
    w.put(m.alpha_cutoff);
    w.put(static_cast<std::uint8_t>(m.double_sided ? 1 : 0));
    w.put(m.metallic);
    w.put(m.roughness);
  }
  w.put(static_cast<std::uint32_t>(g.images.size()));
  for (const SourceImage& im : g.images) {
    w.put(im.name);
    w.put(im.mime_type);
    if (im.bytes.size() > std::numeric_limits<std::uint32_t>::max())
      throw std::invalid_argument("refusing to write source image \"" + im.name + "\" of " +
                                  std::to_string(im.bytes.size()) + " bytes, at most 4294967295 are stored");
    w.put(im.bytes);  // u32 length + the encoded image, whole
  }
}

std::size_t source_size(const SourceGeometry& g) {
  std::size_t size = 12 + g.materials.size() * kMaterialSize;
  for (const SourcePrimitive& p : g.primitives)
    size += kPrimitiveHeader + p.name.size() + 12 * (p.positions.size() + p.normals.size()) +
            8 * p.uvs.size() + 4 * p.indices.size();
  for (const SourceMaterial& m : g.materials) size += m.name.size();
  for (const SourceImage& im : g.images)
    size += kImageHeader + im.name.size() + im.mime_type.size() + im.bytes.size();
  return size;
}

}  // namespace

std::string encode_sylt(const Tree& tree) {
  if (auto errors = validate_tree(tree); !errors.empty()) {
    std::string msg = "refusing to write an invalid tree:";
    for (const auto& e : errors) msg += "\n  " + e;
    throw std::invalid_argument(msg);
  }
  std::size_t size =
      kHeaderSize + kChecksumSize + 256 + tree.leaves.size() * kLeafSize + tree.needles.size() * kNeedleSize;
  for (const Branch& b : tree.branches) size += kBranchHeader + b.nodes.size() * kNodeSize;
  size += source_size(tree.source);
  Writer w;
  w.out.reserve(size);
  // Header.
  w.out.append(kSyltMagic, sizeof kSyltMagic);
  w.put(kSyltVersion);
  w.put(std::uint32_t{0});  // flags, reserved
  // Metadata and materials.
  w.put(tree.name);
  w.put(tree.materials.bark_texture);
  w.put(tree.materials.leaf_texture);
  w.put(tree.materials.bark_color);
  w.put(tree.materials.leaf_color);
  w.put(static_cast<std::uint8_t>(tree.materials.leaf_kind));
  w.put(tree.materials.atlas_columns);
  w.put(tree.materials.atlas_rows);
  w.put(static_cast<std::uint32_t>(tree.materials.cell_coverage.size()));
  for (float c : tree.materials.cell_coverage) w.put(c);
  w.put(tree.materials.bark_tint);
  w.put(tree.materials.bark_tint_from_m);
  w.put(tree.materials.bark_tint_to_m);
  // Skeleton.
  w.put(static_cast<std::uint32_t>(tree.branches.size()));
  for (const Branch& b : tree.branches) {
    w.put(b.parent);
    w.put(b.parent_node);
    w.put(b.parent_t);
    w.put(b.level);
    w.put(static_cast<std::uint32_t>(b.nodes.size()));
    for (const Node& n : b.nodes) {
      w.put(n.position);
      w.put(n.radius);
    }
  }
  // Foliage.
  w.put(static_cast<std::uint32_t>(tree.leaves.size()));
  for (const Leaf& l : tree.leaves) {
    w.put(l.branch);
    w.put(l.position);
    w.put(l.direction);
    w.put(l.normal);
    w.put(l.length);
    w.put(l.width);
    w.put(l.variant);
  }
  w.put(static_cast<std::uint32_t>(tree.needles.size()));
  for (const Needle& n : tree.needles) {
    w.put(n.branch);
    w.put(n.base);
    w.put(n.tip);
    w.put(n.radius);
  }
  // Imported mesh (version 3).
  put_source(w, tree.source);
  // Checksum of everything before it.
  w.put(fnv1a64(w.out));
  return std::move(w.out);
}

namespace {

// The body's sections, in file order (encode_sylt writes them so); every read bounds-checked.
void read_materials(Reader& r, Materials& m) {
  m.bark_texture = r.string("bark texture");
  m.leaf_texture = r.string("leaf texture");
  m.bark_color = r.color("bark colour");
  m.leaf_color = r.color("leaf colour");
  const auto kind = r.get<std::uint8_t>("leaf kind");
  if (kind > 2) r.fail("unknown leaf kind " + std::to_string(kind));
  m.leaf_kind = static_cast<LeafKind>(kind);
  m.atlas_columns = r.get<std::uint8_t>("atlas columns");
  m.atlas_rows = r.get<std::uint8_t>("atlas rows");
  const auto nc = r.count(4, "cell coverage count");
  if (nc > 256) r.fail("cell coverage count " + std::to_string(nc) + " exceeds 256");
  m.cell_coverage.resize(nc);
  for (float& c : m.cell_coverage) c = r.get<float>("cell coverage");
  m.bark_tint = r.color("bark tint");
  m.bark_tint_from_m = r.get<float>("bark tint from");
  m.bark_tint_to_m = r.get<float>("bark tint to");
}

void read_skeleton(Reader& r, Tree& t) {
  const auto nb = r.count(kBranchHeader, "branch count");
  t.branches.resize(nb);
  for (auto& b : t.branches) {
    b.parent = r.get<std::int32_t>("branch parent");
    b.parent_node = r.get<std::uint32_t>("branch parent node");
    b.parent_t = r.get<double>("branch parent t");
    b.level = r.get<std::uint32_t>("branch level");
    const auto nn = r.count(kNodeSize, "node count");
    b.nodes.resize(nn);
    for (auto& n : b.nodes) {
      n.position = r.vec3("node position");
      n.radius = r.get<double>("node radius");
    }
  }
}

void read_foliage(Reader& r, Tree& t) {
  const auto nl = r.count(kLeafSize, "leaf count");
  t.leaves.resize(nl);
  for (auto& l : t.leaves) {
    l.branch = r.get<std::uint32_t>("leaf branch");
    l.position = r.vec3f("leaf position");
    l.direction = r.vec3f("leaf direction");
    l.normal = r.vec3f("leaf normal");
    l.length = r.get<float>("leaf length");
    l.width = r.get<float>("leaf width");
    l.variant = r.get<std::uint8_t>("leaf variant");
  }
  const auto nd = r.count(kNeedleSize, "needle count");
  t.needles.resize(nd);
  for (auto& n : t.needles) {
    n.branch = r.get<std::uint32_t>("needle branch");
    n.base = r.vec3f("needle base");
    n.tip = r.vec3f("needle tip");
    n.radius = r.get<float>("needle radius");
  }
}

// Version 3's imported mesh. Running totals enforce kMaxSourceVertices/Triangles before each
// array is allocated, on top of the bytes-left check every count gets.
void read_primitive(Reader& r, SourcePrimitive& p, std::size_t& vertices, std::size_t& triangles) {
  p.name = r.string("source primitive name");
  p.material = r.get<std::uint32_t>("source primitive material");
  const auto attributes = r.get<std::uint8_t>("source primitive attributes");
  if (attributes & ~(kHasNormals | kHasUvs))
    r.fail("unknown source primitive attributes " + std::to_string(attributes));
  const bool normals = attributes & kHasNormals, uvs = attributes & kHasUvs;
  const std::size_t at = r.pos();
  const auto nv = r.count(12 + (normals ? 12 : 0) + (uvs ? 8 : 0), "source vertex count");
  vertices += nv;
  if (vertices > kMaxSourceVertices)
    r.fail_at(
        at, "source vertices " + std::to_string(vertices) + " exceed " + std::to_string(kMaxSourceVertices));
  p.positions.resize(nv);
  for (Vec3f& v : p.positions) v = r.vec3f("source position");
  if (normals) {
    p.normals.resize(nv);
    for (Vec3f& v : p.normals) v = r.vec3f("source normal");
  }
  if (uvs) {
    p.uvs.resize(nv);
    for (auto& uv : p.uvs) {
      uv[0] = r.get<float>("source uv");
      uv[1] = r.get<float>("source uv");
    }
  }
  const std::size_t at_indices = r.pos();
  const auto ni = r.count(4, "source index count");
  triangles += ni / 3;
  if (triangles > kMaxSourceTriangles)
    r.fail_at(at_indices, "source triangles " + std::to_string(triangles) + " exceed " +
                              std::to_string(kMaxSourceTriangles));
  p.indices.resize(ni);
  for (std::uint32_t& i : p.indices) i = r.get<std::uint32_t>("source index");
}

void read_source(Reader& r, SourceGeometry& g) {
  std::size_t vertices = 0, triangles = 0;
  g.primitives.resize(r.count(kPrimitiveHeader, "source primitive count"));
  for (SourcePrimitive& p : g.primitives) read_primitive(r, p, vertices, triangles);
  g.materials.resize(r.count(kMaterialSize, "source material count"));
  for (SourceMaterial& m : g.materials) {
    m.name = r.string("source material name");
    for (float& c : m.base_color) c = r.get<float>("source base colour");
    m.base_color_image = r.get<std::int32_t>("source base colour image");
    const auto mode = r.get<std::uint8_t>("source alpha mode");
    if (mode > 2) r.fail("unknown source alpha mode " + std::to_string(mode));
    m.alpha_mode = static_cast<AlphaMode>(mode);
    m.alpha_cutoff = r.get<float>("source alpha cutoff");
    const auto sided = r.get<std::uint8_t>("source double sided");
    if (sided > 1) r.fail("source double sided must be 0 or 1, is " + std::to_string(sided));
    m.double_sided = sided == 1;
    m.metallic = r.get<float>("source metallic");
    m.roughness = r.get<float>("source roughness");
  }
  g.images.resize(r.count(kImageHeader, "source image count"));
  for (SourceImage& im : g.images) {
    im.name = r.string("source image name");
    im.mime_type = r.string("source image mime type");
    im.bytes = r.string("source image bytes", std::numeric_limits<std::uint32_t>::max());
  }
}

}  // namespace

Tree decode_sylt(std::string_view bytes, std::string_view source) {
  const std::string src(source);
  // 1. Header: magic and version first, so a wrong file type or a newer file says so.
  if (bytes.empty()) throw TreeFormatError(src + ": empty file");
  if (bytes.size() < sizeof kSyltMagic || std::memcmp(bytes.data(), kSyltMagic, sizeof kSyltMagic) != 0)
    throw TreeFormatError(src + ": not a .sylt file (bad magic)");
  if (bytes.size() < kHeaderSize + kChecksumSize)
    throw TreeFormatError(src + ": truncated: " + std::to_string(bytes.size()) +
                          " bytes is shorter than the header and checksum");
  Reader r(bytes.substr(0, bytes.size() - kChecksumSize), source);
  (void)r.get<std::uint64_t>("magic");
  const auto version = r.get<std::uint32_t>("version");
  if (version < kSyltOldestVersion || version > kSyltVersion)
    throw TreeFormatError(src + ": unsupported .sylt version " + std::to_string(version) +
                          " (this build reads versions " + std::to_string(kSyltOldestVersion) + " to " +
                          std::to_string(kSyltVersion) + ")");
  // 2. Checksum over everything but the last 8 bytes: catches truncation and bit rot.
  {
    Reader tail(bytes.substr(bytes.size() - kChecksumSize), source);
    const auto stored = tail.get<std::uint64_t>("checksum");
    if (stored != fnv1a64(bytes.substr(0, bytes.size() - kChecksumSize)))
      throw TreeFormatError(src + ": checksum mismatch (file truncated or corrupt)");
  }
  // 3. Body, every read bounds-checked (a crafted file may carry a valid checksum).
  Tree t;
  if (r.get<std::uint32_t>("flags") != 0) r.fail("reserved flags must be 0");
  t.name = r.string("name");
  read_materials(r, t.materials);
  read_skeleton(r, t);
  read_foliage(r, t);
  if (version >= 3) read_source(r, t.source);  // version 2 has no imported mesh
  if (r.left() != 0) r.fail(std::to_string(r.left()) + " unexpected bytes before the checksum");
  // 4. Semantic invariants.
  if (auto errors = validate_tree(t, 1); !errors.empty())
    throw TreeFormatError(src + ": invalid tree: " + errors.front());
  return t;
}

void write_sylt(const std::filesystem::path& path, const Tree& tree) {
  const std::string bytes = encode_sylt(tree);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw std::runtime_error(path.string() + ": cannot open for writing");
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  f.close();
  if (!f) throw std::runtime_error(path.string() + ": write failed");
}

Tree read_sylt(const std::filesystem::path& path) {
  std::string bytes;
  try {
    bytes = fileio::read_file(path);
  } catch (const fileio::FileReadError& e) {
    throw TreeFormatError(e.what());
  }
  return decode_sylt(bytes, path.string());
}

}  // namespace sylva::tree
