#include "libs/image/image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <stdexcept>

#include "libs/image/image_io.h"
#include "libs/image/png.h"
#include "libs/image/resample.h"
#include "tests/support/test_support.h"

namespace sylva::image {
namespace {

Image gradient(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.set(x, y,
              {std::uint8_t(x * 7), std::uint8_t(y * 5), std::uint8_t(x ^ y), std::uint8_t(200 + x % 50)});
  return img;
}

// Pixel access is top-left based and the fill constructor fills every pixel.
TEST(Image, FillAndAccess) {
  Image img(3, 2, {1, 2, 3, 4});
  EXPECT_EQ(img.width(), 3);
  EXPECT_EQ(img.height(), 2);
  EXPECT_EQ(img.bytes().size(), 24u);
  EXPECT_EQ(img.at(2, 1), (Rgba8{1, 2, 3, 4}));
  img.set(2, 1, {9, 8, 7, 6});
  EXPECT_EQ(img.bytes()[(1 * 3 + 2) * 4], 9);
  EXPECT_EQ(img.at(0, 0), (Rgba8{1, 2, 3, 4}));
}

// A PNG written and read back gives the same pixels, alpha included.
TEST(ImageIo, PngRoundTrip) {
  test::TempDir dir;
  const Image img = gradient(37, 23);
  write_png(img, dir / "a.png");
  EXPECT_EQ(read_image(dir / "a.png"), img);
}

// The same image always encodes to the same bytes (no timestamps), file and memory agree, and
// no temporary file is left behind.
TEST(ImageIo, PngBytesAreDeterministic) {
  test::TempDir dir;
  const Image img = gradient(64, 16);
  write_png(img, dir / "a.png");
  write_png(img, dir / "b.png");
  const std::string a = test::read_file(dir / "a.png");
  EXPECT_EQ(a, test::read_file(dir / "b.png"));
  const auto mem = encode_png(img);
  EXPECT_EQ(a, std::string(mem.begin(), mem.end()));
  EXPECT_EQ(a.find("tIME"), std::string::npos);
  int files = 0;
  for (auto& e : std::filesystem::directory_iterator(dir.path())) (void)e, ++files;
  EXPECT_EQ(files, 2);
}

// A lower zlib level gives other (here: larger) bytes of the same pixels, deterministically;
// levels outside 0..9 are refused.
TEST(ImageIo, PngZlibLevelChangesBytesNotPixels) {
  test::TempDir dir;
  Image img(256, 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 256; ++x)
      img.set(x, y, {std::uint8_t((x * x + y) % 251), std::uint8_t(x / 3), std::uint8_t(y * 3), 255});
  PngOptions fast;
  fast.zlib_level = 1;
  const auto a = encode_png(img, fast), b = encode_png(img);
  EXPECT_NE(a, b);
  EXPECT_GT(a.size(), b.size());
  EXPECT_EQ(a, encode_png(img, fast));
  EXPECT_EQ(b, encode_png(img, PngOptions{}));
  write_png(img, dir / "fast.png", fast);
  EXPECT_EQ(test::read_file(dir / "fast.png"), std::string(a.begin(), a.end()));
  EXPECT_EQ(decode_png(std::string_view(reinterpret_cast<const char*>(a.data()), a.size())), img);
  PngOptions bad;
  bad.zlib_level = 10;
  EXPECT_THROW(encode_png(img, bad), ImageError);
}

// Reading an RGB file yields opaque RGBA; a grey file is replicated to RGB.
TEST(ImageIo, RgbAndGreyFilesBecomeOpaqueRgba) {
  test::TempDir dir;
  const unsigned char rgb[2 * 3] = {10, 20, 30, 40, 50, 60};
  auto out = OIIO::ImageOutput::create("png");
  ASSERT_TRUE(out->open((dir / "rgb.png").string(), OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb));
  out->close();
  const Image back = read_image(dir / "rgb.png");
  EXPECT_EQ(back.at(0, 0), (Rgba8{10, 20, 30, 255}));
  EXPECT_EQ(back.at(1, 0), (Rgba8{40, 50, 60, 255}));

  const unsigned char grey[2] = {7, 250};
  out = OIIO::ImageOutput::create("png");
  ASSERT_TRUE(out->open((dir / "grey.png").string(), OIIO::ImageSpec(2, 1, 1, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, grey));
  out->close();
  EXPECT_EQ(read_image(dir / "grey.png").at(1, 0), (Rgba8{250, 250, 250, 255}));
}

// The PNG carries no text or time chunks: only what the format needs.
TEST(ImageIo, PngHasNoMetadataChunks) {
  const auto png = encode_png(gradient(8, 8));
  std::vector<std::string> chunks;
  for (std::size_t at = 8; at + 8 <= png.size();) {
    const std::size_t n = (std::size_t(png[at]) << 24) | (std::size_t(png[at + 1]) << 16) |
                          (std::size_t(png[at + 2]) << 8) | std::size_t(png[at + 3]);
    chunks.emplace_back(reinterpret_cast<const char*>(&png[at + 4]), 4);
    at += 12 + n;
  }
  for (const auto& c : chunks) {
    EXPECT_TRUE(c == "IHDR" || c == "IDAT" || c == "IEND" || c == "oFFs") << "unexpected chunk " << c;
  }
  EXPECT_EQ(chunks.front(), "IHDR");
  EXPECT_EQ(chunks.back(), "IEND");
}

// libpng writes exactly the bytes OpenImageIO's PNG writer wrote with the settings sylva used
// (level 6, straight alpha, its oFFs chunk): moving PNG output off OpenImageIO changed no file.
TEST(ImageIo, LibpngBytesEqualOpenImageIoBytes) {
  for (const Image& img : {gradient(64, 16), gradient(1, 1), gradient(300, 7), Image(33, 33, {9, 9, 9, 0})}) {
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    auto out = OIIO::ImageOutput::create("png");
    OIIO::ImageSpec spec(img.width(), img.height(), 4, OIIO::TypeDesc::UINT8);
    spec.attribute("png:compressionLevel", 6);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    ASSERT_TRUE(out->set_ioproxy(&proxy));
    ASSERT_TRUE(out->open("memory.png", spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, img.bytes().data()));
    out->close();
    const auto ours = encode_png(img);
    EXPECT_EQ(std::vector<unsigned char>(ours.begin(), ours.end()), bytes)
        << img.width() << "x" << img.height();
  }
}

// read_png (libpng) decodes what OpenImageIO reads: RGBA exactly, RGB opaque, grey replicated.
TEST(ImageIo, ReadPngDecodesRgbaRgbAndGrey) {
  test::TempDir dir;
  const Image img = gradient(37, 23);
  write_png(img, dir / "a.png");
  EXPECT_EQ(read_png(dir / "a.png"), img);
  const unsigned char rgb[2 * 3] = {10, 20, 30, 40, 50, 60};
  auto out = OIIO::ImageOutput::create("png");
  ASSERT_TRUE(out->open((dir / "rgb.png").string(), OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgb));
  out->close();
  EXPECT_EQ(read_png(dir / "rgb.png"), read_image(dir / "rgb.png"));
  EXPECT_EQ(read_png(dir / "rgb.png").at(1, 0), (Rgba8{40, 50, 60, 255}));
  const unsigned char grey[2] = {7, 250};
  out = OIIO::ImageOutput::create("png");
  ASSERT_TRUE(out->open((dir / "grey.png").string(), OIIO::ImageSpec(2, 1, 1, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, grey));
  out->close();
  EXPECT_EQ(read_png(dir / "grey.png").at(1, 0), (Rgba8{250, 250, 250, 255}));
  test::write_file(dir / "cut.png", test::read_file(dir / "a.png").substr(0, 60));
  try {
    read_png(dir / "cut.png");
    FAIL() << "expected ImageError";
  } catch (const ImageError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "cut.png").string() + ": error: cannot decode image: file is truncated");
  }
}

// Errors name the file and say what went wrong, in one line.
TEST(ImageIo, ErrorsNameTheFile) {
  test::TempDir dir;
  try {
    read_image(dir / "missing.png");
    FAIL() << "expected ImageError";
  } catch (const ImageError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "missing.png").string() + ": error: no such image file");
  }
  test::write_file(dir / "junk.png", "this is not a png");
  try {
    read_image(dir / "junk.png");
    FAIL() << "expected ImageError";
  } catch (const ImageError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind((dir / "junk.png").string() + ": error: ", 0), 0u) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  EXPECT_THROW(write_png(Image(4, 4), dir / "no_such_dir" / "x.png"), ImageError);
  EXPECT_THROW(write_png(Image(), dir / "empty.png"), ImageError);
}

}  // namespace
}  // namespace sylva::image

// Supersampling: a 2x2 block of black and white averages to 50 % linear grey (sRGB 188), not to
// sRGB 128; a uniform image stays as it is; sizes that do not divide are refused.
TEST(Downsample, AveragesInLinearLight) {
  sylva::image::Image img(4, 2, {10, 20, 30, 255});
  img.set(0, 0, {0, 0, 0, 255});
  img.set(1, 0, {255, 255, 255, 255});
  img.set(0, 1, {0, 0, 0, 255});
  img.set(1, 1, {255, 255, 255, 255});
  const sylva::image::Image small = sylva::image::downsample(img, 2);
  ASSERT_EQ(small.width(), 2);
  ASSERT_EQ(small.height(), 1);
  EXPECT_NEAR(small.at(0, 0).r, 188, 1);
  EXPECT_EQ(small.at(0, 0).a, 255);
  EXPECT_NEAR(small.at(1, 0).r, 10, 1);
  EXPECT_NEAR(small.at(1, 0).b, 30, 1);
  EXPECT_EQ(sylva::image::downsample(img, 1), img);
  EXPECT_THROW(sylva::image::downsample(img, 3), std::invalid_argument);
}

// Straight alpha: one covered red pixel among three transparent ones gives red at coverage 1/4,
// not a dark red (the transparent pixels' black must not enter the colour).
TEST(Downsample, WeightsColourByCoverage) {
  sylva::image::Image img(2, 2, {0, 0, 0, 0});
  img.set(1, 1, {200, 40, 10, 255});
  const sylva::image::Image small = sylva::image::downsample(img, 2);
  EXPECT_NEAR(small.at(0, 0).r, 200, 1);
  EXPECT_NEAR(small.at(0, 0).g, 40, 1);
  EXPECT_NEAR(small.at(0, 0).a, 64, 1);
}
