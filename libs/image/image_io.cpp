// OpenImageIO is used through its in-memory I/O proxies: encoding into a byte vector first lets
// write_png() write atomically and lets callers hash or cache PNG bytes without touching disk.
#include "libs/image/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <fstream>
#include <system_error>
#include <unistd.h>

namespace sylva::image {
namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& why) {
  throw ImageError(path.string() + ": error: " + why);
}

std::string oiio_message(const std::string& s) {
  // OIIO messages may span several lines; keep the report to one.
  std::string out;
  for (char c : s) out += (c == '\n' ? ' ' : c);
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out.empty() ? std::string("unknown OpenImageIO error") : out;
}

}  // namespace

Image read_image(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail(path, "no such image file");
  // Keep alpha straight: by default OIIO premultiplies PNG colour by alpha on read.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) fail(path, "cannot read image: " + oiio_message(OIIO::geterror()));
  const OIIO::ImageSpec& spec = in->spec();
  const int w = spec.width, h = spec.height, nch = spec.nchannels;
  if (w <= 0 || h <= 0 || nch <= 0) fail(path, "image has no pixels");
  std::vector<std::uint8_t> raw(std::size_t(w) * std::size_t(h) * std::size_t(nch));
  if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, raw.data()))
    fail(path, "cannot decode image: " + oiio_message(in->geterror()));
  in->close();

  // Map the channels to RGBA; a second channel of a two-channel image is alpha.
  const int alpha = spec.alpha_channel >= 0 ? spec.alpha_channel : (nch == 2 ? 1 : (nch >= 4 ? 3 : -1));
  Image img(w, h);
  auto& out = img.bytes();
  for (std::size_t i = 0; i < img.pixel_count(); ++i) {
    const std::uint8_t* p = &raw[i * std::size_t(nch)];
    std::uint8_t* q = &out[i * 4];
    if (nch <= 2) {
      q[0] = q[1] = q[2] = p[0];
    } else {
      q[0] = p[0];
      q[1] = p[1];
      q[2] = p[2];
    }
    q[3] = alpha >= 0 ? p[alpha] : 255;
  }
  return img;
}

std::vector<std::uint8_t> encode_png(const Image& img) {
  if (img.empty()) throw ImageError("<png>: error: cannot encode an empty image");
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  auto out = OIIO::ImageOutput::create("png");
  if (!out) throw ImageError("<png>: error: OpenImageIO has no PNG writer");
  // A fresh spec carries no metadata; only the format's own settings are fixed explicitly so
  // that the bytes do not depend on a library default.
  OIIO::ImageSpec spec(img.width(), img.height(), 4, OIIO::TypeDesc::UINT8);
  spec.attribute("png:compressionLevel", 6);
  // Our pixels are straight alpha, which is what PNG stores; without this OIIO would treat them
  // as premultiplied and divide colour by alpha on the way out.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  if (!out->set_ioproxy(&proxy)) throw ImageError("<png>: error: PNG writer cannot write to memory");
  if (!out->open("memory.png", spec))
    throw ImageError("<png>: error: cannot encode PNG: " + oiio_message(out->geterror()));
  if (!out->write_image(OIIO::TypeDesc::UINT8, img.bytes().data()))
    throw ImageError("<png>: error: cannot encode PNG: " + oiio_message(out->geterror()));
  out->close();
  return {bytes.begin(), bytes.end()};
}

void write_png(const Image& img, const std::filesystem::path& path) {
  std::vector<std::uint8_t> bytes;
  try {
    bytes = encode_png(img);
  } catch (const ImageError& e) {
    std::string msg = e.what();
    fail(path, msg.substr(msg.find("error: ") + 7));
  }
  std::filesystem::path tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) fail(path, "cannot open for writing");
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    f.close();
    if (!f) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      fail(path, "write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    fail(path, "cannot rename temporary file into place");
  }
}

}  // namespace sylva::image
