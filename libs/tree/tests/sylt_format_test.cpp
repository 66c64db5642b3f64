#include "libs/tree/sylt_format.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "libs/tree/tests/sample_tree.h"
#include "tests/support/test_support.h"

namespace sylva::tree {
namespace {

using testing::sample_tree;

// Bytes of version 2's materials after the colours for the sample tree (no coverage list):
// leaf kind, atlas columns, rows (3), coverage count (4), bark tint (12), tint heights (8).
constexpr std::size_t kMaterials2 = 3 + 4 + 12 + 8;

std::string error_of(std::string_view bytes) {
  try {
    decode_sylt(bytes, "t.sylt");
  } catch (const TreeFormatError& e) {
    return e.what();
  }
  return "";
}

// Rewrites the trailing checksum so a deliberately corrupted body reaches the parser.
std::string reseal(std::string bytes) {
  const std::uint64_t h = fnv1a64(std::string_view(bytes).substr(0, bytes.size() - 8));
  std::memcpy(bytes.data() + bytes.size() - 8, &h, 8);  // tests run on little-endian hosts
  return bytes;
}

// Values that print identically but differ in the last bit, plus extremes, survive exactly.
TEST(SyltFormat, RoundTripIsBitExact) {
  Tree t = sample_tree();
  t.branches[0].nodes[1].position.x = 0.1 + 0.2;  // 0.30000000000000004
  t.branches[0].nodes[1].radius = std::nextafter(0.18, 1.0);
  t.branches[0].nodes[2].position.z = -std::numeric_limits<double>::denorm_min();
  t.branches[1].parent_t = 0;
  t.leaves[0].length = std::nextafter(0.1f, 1.0f);
  t.name = "oak/adult \xc3\xa9";
  const std::string bytes = encode_sylt(t);
  const Tree back = decode_sylt(bytes);
  EXPECT_EQ(back, t);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(back.branches[0].nodes[2].position.z),
            std::bit_cast<std::uint64_t>(t.branches[0].nodes[2].position.z));
  EXPECT_EQ(encode_sylt(back), bytes);  // encoding is deterministic
}

TEST(SyltFormat, FileRoundTrip) {
  sylva::test::TempDir dir;
  const Tree t = sample_tree();
  write_sylt(dir / "a.sylt", t);
  EXPECT_EQ(read_sylt(dir / "a.sylt"), t);
}

TEST(SyltFormat, HeaderStartsWithMagicAndVersion) {
  const std::string bytes = encode_sylt(sample_tree());
  ASSERT_GE(bytes.size(), 16u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("SYLT\r\n\x1a\n", 8));
  EXPECT_EQ(bytes.substr(8, 4), std::string("\x03\x00\x00\x00", 4));
}

// Issue 15 item 6: the writer used to accept names the reader rejects. Now a name of exactly the
// limit round-trips and one byte more is refused when writing, naming the limit.
TEST(SyltFormat, WriterAndReaderAgreeOnTheNameLimit) {
  Tree t = sample_tree();
  t.name.assign(kMaxTextBytes, 'n');
  EXPECT_EQ(decode_sylt(encode_sylt(t)).name, t.name);
  t.name.push_back('n');
  try {
    encode_sylt(t);
    FAIL() << "a name of " << t.name.size() << " bytes was written";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("the tree name is 65537 bytes, at most 65536 are stored"),
              std::string::npos)
        << e.what();
  }
  t = sample_tree();
  t.materials.bark_texture.assign(kMaxTextBytes + 1, 'b');
  EXPECT_THROW(encode_sylt(t), std::invalid_argument);
}

TEST(SyltFormat, EmptyTreeRoundTrips) {
  Tree t;
  EXPECT_EQ(decode_sylt(encode_sylt(t)), t);
}

// Every truncation of a valid file gives an error, never a crash or a tree.
TEST(SyltFormat, EveryTruncationIsAnError) {
  const std::string bytes = encode_sylt(sample_tree());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    const std::string msg = error_of(std::string_view(bytes).substr(0, n));
    EXPECT_FALSE(msg.empty()) << "truncated to " << n << " bytes";
    EXPECT_EQ(msg.rfind("t.sylt: ", 0), 0u) << msg;
  }
}

// Flipping any single byte is caught (by magic, version or checksum).
TEST(SyltFormat, EveryByteFlipIsAnError) {
  const std::string bytes = encode_sylt(sample_tree());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    std::string bad = bytes;
    bad[i] = static_cast<char>(bad[i] ^ 0x5a);
    EXPECT_FALSE(error_of(bad).empty()) << "flip at " << i;
  }
}

TEST(SyltFormat, ExactMessages) {
  const std::string bytes = encode_sylt(sample_tree());
  EXPECT_EQ(error_of(""), "t.sylt: empty file");
  EXPECT_EQ(error_of("hello"), "t.sylt: not a .sylt file (bad magic)");
  EXPECT_EQ(error_of(bytes.substr(0, 12)),
            "t.sylt: truncated: 12 bytes is shorter than the header and checksum");
  std::string v2 = bytes;
  v2[8] = 1;
  EXPECT_EQ(error_of(v2), "t.sylt: unsupported .sylt version 1 (this build reads versions 2 to 3)");
  v2[8] = 4;
  EXPECT_EQ(error_of(v2), "t.sylt: unsupported .sylt version 4 (this build reads versions 2 to 3)");
  EXPECT_EQ(error_of(bytes.substr(0, bytes.size() - 1)),
            "t.sylt: checksum mismatch (file truncated or corrupt)");
}

// A body that is corrupt but carries a matching checksum is still rejected with the offset.
TEST(SyltFormat, CorruptCountWithValidChecksum) {
  std::string bytes = encode_sylt(sample_tree());
  // The branch count follows header(16) + name(4+6) + two textures (4+8, 4+10) + colours(24) +
  // leaf kind, atlas grid, coverage count, bark tint (kMaterials2).
  const std::size_t at = 16 + 10 + 12 + 14 + 24 + kMaterials2;
  std::uint32_t huge = 0x7fffffff;
  std::memcpy(bytes.data() + at, &huge, 4);
  const std::string msg = error_of(reseal(bytes));
  EXPECT_NE(msg.find("t.sylt: byte 103: branch count 2147483647 needs"), std::string::npos) << msg;
}

TEST(SyltFormat, InvalidTreeInsideFileIsRejected) {
  std::string bytes = encode_sylt(sample_tree());
  // Branch 1's parent field: after branch count (4) and branch 0 (24 + 4 * 32).
  const std::size_t at = 16 + 10 + 12 + 14 + 24 + kMaterials2 + 4 + 24 + 4 * 32;
  std::int32_t self = 1;
  std::memcpy(bytes.data() + at, &self, 4);
  EXPECT_EQ(error_of(reseal(bytes)), "t.sylt: invalid tree: branch 1: parent 1 is not before it");
}

TEST(SyltFormat, NanRadiusIsRejected) {
  std::string bytes = encode_sylt(sample_tree());
  const std::size_t at = 16 + 10 + 12 + 14 + 24 + kMaterials2 + 4 + 24 + 24;  // branch 0, node 0 radius
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(bytes.data() + at, &nan, 8);
  EXPECT_EQ(error_of(reseal(bytes)),
            "t.sylt: invalid tree: branch 0: node 0: radius must be finite and >= 0");
}

// Version 2's materials: leaf kind, a 4x2 atlas with its coverages and the bark tint survive
// the round trip; an unknown leaf kind and a variant outside the atlas are refused.
TEST(SyltFormat, CardMaterialsRoundTrip) {
  Tree t = sample_tree();
  t.materials.leaf_kind = LeafKind::kShootCards;
  t.materials.atlas_columns = 4;
  t.materials.atlas_rows = 2;
  t.materials.cell_coverage = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f};
  t.materials.bark_tint = {0.5f, 0.4f, 0.3f};
  t.materials.bark_tint_from_m = 2;
  t.materials.bark_tint_to_m = 5;
  t.leaves[0].variant = 7;
  const std::string bytes = encode_sylt(t);
  EXPECT_EQ(decode_sylt(bytes), t);
  std::string bad = bytes;
  bad[16 + 10 + 12 + 14 + 24] = 3;  // the leaf kind byte
  EXPECT_EQ(error_of(reseal(bad)), "t.sylt: byte 77: unknown leaf kind 3");
  t.leaves[0].variant = 8;
  EXPECT_THROW(encode_sylt(t), std::invalid_argument);
  t.leaves[0].variant = 0;
  t.materials.cell_coverage.pop_back();
  EXPECT_EQ(validate_tree(t).front(), "materials: 7 cell coverages for 8 atlas cells");
}

TEST(SyltFormat, WriterRefusesInvalidTree) {
  Tree t = sample_tree();
  t.branches[1].parent_node = 9;
  EXPECT_THROW(encode_sylt(t), std::invalid_argument);
}

TEST(SyltFormat, MissingFile) { EXPECT_THROW(read_sylt("/nonexistent/x.sylt"), TreeFormatError); }

// Fuzz-style: thousands of deterministic random corruptions of a valid file, resealed so the
// body parser (not just the checksum) sees them. Every outcome is a valid tree or a
// TreeFormatError — never a crash, a hang or another exception type.
TEST(SyltFormat, RandomCorruptionsNeverCrash) {
  const std::string good = encode_sylt(testing::sample_tree());
  sylva::test::XorShift64 next(0x9e3779b97f4a7c15ull);
  int rejected = 0;
  for (int i = 0; i < 5000; ++i) {
    std::string bad = good;
    const int edits = 1 + static_cast<int>(next() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = 16 + next() % (bad.size() - 24);  // keep magic/version, body only
      switch (next() % 3) {
        case 0:
          bad[at] = static_cast<char>(next());
          break;
        case 1:
          bad.erase(at, 1 + next() % 8);
          break;
        default:
          bad.insert(at, std::string(1 + next() % 8, static_cast<char>(next())));
          break;
      }
    }
    try {
      (void)decode_sylt(reseal(bad), "fuzz.sylt");
    } catch (const TreeFormatError&) {
      ++rejected;
    }
  }
  EXPECT_GT(rejected, 4000);
}

// Version 3: the imported mesh. Several primitives (one with normals and uvs, one with uvs
// only, one with neither), three materials (opaque, mask, blend), two images whose bytes hold
// NUL and high bytes; floats that differ in the last bit survive exactly.
Tree tree_with_source() {
  Tree t = sample_tree();
  t.source = testing::sample_source();
  t.source.primitives[0].positions[1].x = std::nextafter(0.1f, 1.0f);
  t.source.primitives[1].uvs[0][0] = -std::numeric_limits<float>::denorm_min();
  t.source.materials[1].alpha_cutoff = std::nextafter(0.3f, 0.0f);
  return t;
}

// Where the source section starts: after everything version 2 had.
std::size_t source_offset(const Tree& t) {
  Tree bare = t;
  bare.source = {};
  return encode_sylt(bare).size() - 8 - 12;  // its three empty source counts and the checksum
}

TEST(SyltFormat, SourceGeometryRoundTripIsBitExact) {
  const Tree t = tree_with_source();
  const std::string bytes = encode_sylt(t);
  const Tree back = decode_sylt(bytes, "t.sylt");
  EXPECT_EQ(back, t);
  EXPECT_EQ(back.source.primitives[2].normals.size(), 0u);
  EXPECT_EQ(back.source.primitives[1].normals.size(), 0u);
  EXPECT_EQ(back.source.primitives[1].uvs.size(), 3u);
  EXPECT_EQ(std::bit_cast<std::uint32_t>(back.source.primitives[1].uvs[0][0]), 0x80000001u);
  EXPECT_EQ(back.source.images[0].bytes, std::string("\x89PNG\r\n\x1a\n\0bark", 13));
  // Size: 3 primitives (17-byte headers, names 20 + 16 + 9, vertex arrays 4 * 32 + 3 * 20 + 3 * 12,
  // indices 6 + 3 + 3), 3 materials (38 bytes, names 4 + 6 + 4), 2 images (12 bytes, names 8 + 8,
  // mime types 9 + 10, bytes 13 + 8), and the 3 counts.
  const std::size_t section = 3 * 17 + 45 + 128 + 60 + 36 + 12 * 4 + 3 * 38 + 14 + 2 * 12 + 16 + 19 + 21 + 12;
  EXPECT_EQ(bytes.size(), source_offset(t) + section + 8);
  EXPECT_EQ(encode_sylt(back), bytes);  // deterministic
  EXPECT_EQ(encode_sylt(tree_with_source()), bytes);
}

// Version 2 files (written before the imported mesh) still decode, with an empty source; a
// version 2 header over a version 3 body is refused (its source counts are unexpected bytes).
TEST(SyltFormat, ReadsVersionTwo) {
  const Tree t = sample_tree();
  std::string v3 = encode_sylt(t);
  std::string v2 = v3;
  v2.erase(v2.size() - 8 - 12, 12);  // the three empty source counts
  v2[8] = 2;
  EXPECT_EQ(decode_sylt(reseal(v2), "t.sylt"), t);
  std::string mislabelled = v3;
  mislabelled[8] = 2;
  EXPECT_EQ(error_of(reseal(mislabelled)),
            "t.sylt: byte " + std::to_string(v3.size() - 20) + ": 12 unexpected bytes before the checksum");
}

TEST(SyltFormat, EveryTruncationOfVersionThreeIsAnError) {
  const std::string bytes = encode_sylt(tree_with_source());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    const std::string msg = error_of(std::string_view(bytes).substr(0, n));
    EXPECT_EQ(msg.rfind("t.sylt: ", 0), 0u) << "truncated to " << n << " bytes: " << msg;
  }
  // Truncated and resealed, so the body parser (not the checksum) meets the short section.
  for (std::size_t n = source_offset(tree_with_source()); n + 8 < bytes.size(); ++n) {
    std::string cut = bytes.substr(0, n) + std::string(8, '\0');
    const std::string msg = error_of(reseal(cut));
    EXPECT_EQ(msg.rfind("t.sylt: byte ", 0), 0u) << "truncated to " << n << " bytes: " << msg;
  }
}

// A count larger than the bytes left is refused at its offset before anything is allocated.
TEST(SyltFormat, SourceCountsAreCheckedAgainstBytesLeft) {
  const Tree t = tree_with_source();
  const std::string good = encode_sylt(t);
  const std::size_t at = source_offset(t);
  const std::uint32_t huge = 0x7fffffff;
  auto with = [&](std::size_t offset) {
    std::string bytes = good;
    std::memcpy(bytes.data() + offset, &huge, 4);
    return error_of(reseal(bytes));
  };
  const std::string left = std::to_string(good.size() - 8 - at - 4);
  EXPECT_EQ(with(at), "t.sylt: byte " + std::to_string(at) + ": source primitive count 2147483647 needs " +
                          std::to_string(2147483647ull * 17) + " bytes, " + left + " left");
  // Primitive 0's vertex count: after the count, its name (4 + 20), material and attributes.
  const std::size_t vc = at + 4 + 24 + 4 + 1;
  EXPECT_NE(with(vc).find("t.sylt: byte " + std::to_string(vc) + ": source vertex count 2147483647 needs " +
                          std::to_string(2147483647ull * 32) + " bytes, "),
            std::string::npos)
      << with(vc);
  // Image 1's byte count: the last field before its bytes (8) and the checksum.
  const std::size_t ib = good.size() - 8 - 8 - 4;
  EXPECT_EQ(with(ib), "t.sylt: byte " + std::to_string(ib + 4) +
                          ": truncated: source image bytes needs 2147483647 bytes, 8 left");
}

TEST(SyltFormat, SourceFieldMessages) {
  const Tree t = tree_with_source();
  const std::string good = encode_sylt(t);
  const std::size_t at = source_offset(t);
  auto with = [&](std::size_t offset, char value) {
    std::string bytes = good;
    bytes[offset] = value;
    return error_of(reseal(bytes));
  };
  const std::size_t attributes = at + 4 + 24 + 4;
  EXPECT_EQ(with(attributes, 4),
            "t.sylt: byte " + std::to_string(attributes + 1) + ": unknown source primitive attributes 4");
  // Material 0 starts after the three primitives and the material count.
  const std::size_t m0 = at + 4 + (17 + 20 + 128 + 24) + (17 + 16 + 60 + 12) + (17 + 9 + 36 + 12) + 4;
  const std::size_t mode = m0 + 4 + 4 + 16 + 4;
  EXPECT_EQ(with(mode, 3), "t.sylt: byte " + std::to_string(mode + 1) + ": unknown source alpha mode 3");
  EXPECT_EQ(with(mode + 5, 2),
            "t.sylt: byte " + std::to_string(mode + 6) + ": source double sided must be 0 or 1, is 2");
  // An index out of range passes the parser and is refused as an invalid tree.
  const std::size_t index0 = at + 4 + 17 + 20 + 128;
  EXPECT_EQ(
      with(index0, 9),
      "t.sylt: invalid tree: source primitive 0 (\"tree/trunk/br0_trunk\"): index 9 at triangle 0 is not "
      "below 4 positions");
}

TEST(SyltFormat, WriterRefusesInvalidSource) {
  Tree t = tree_with_source();
  t.source.images[0].mime_type = "image/gif";
  try {
    encode_sylt(t);
    FAIL() << "an invalid source was written";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "refusing to write an invalid tree:\n  source image 0 (\"bark.png\"): mime type \"image/gif\" is not "
        "image/png or image/jpeg");
  }
}

// The fuzz-style test again over a file with source geometry.
TEST(SyltFormat, RandomCorruptionsOfSourceNeverCrash) {
  const std::string good = encode_sylt(tree_with_source());
  const std::size_t from = source_offset(tree_with_source());
  sylva::test::XorShift64 next(0x2545f4914f6cdd1dull);
  int rejected = 0;
  for (int i = 0; i < 3000; ++i) {
    std::string bad = good;
    const std::size_t at = from + next() % (bad.size() - 8 - from);
    switch (next() % 3) {
      case 0:
        bad[at] = static_cast<char>(next());
        break;
      case 1:
        bad.erase(at, 1 + next() % 8);
        break;
      default:
        bad.insert(at, std::string(1 + next() % 8, static_cast<char>(next())));
        break;
    }
    try {
      (void)decode_sylt(reseal(bad), "fuzz.sylt");
    } catch (const TreeFormatError&) {
      ++rejected;
    }
  }
  EXPECT_GT(rejected, 2000);
}

}  // namespace
}  // namespace sylva::tree
