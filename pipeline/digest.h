// SHA-256 digests (OpenSSL EVP), the identity of every blob and action in the cache.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace sylva {

// Incremental SHA-256. Not copyable; finish() may be called once.
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;

  void update(std::string_view bytes);
  void update(const void* data, std::size_t size);
  std::array<unsigned char, 32> finish_raw();
  std::string finish_hex();  // 64 lowercase hex digits

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::string sha256_hex(std::string_view bytes);

// Bazel's Digest: the hash and the size of a blob.
struct Digest {
  std::string hash;  // 64 lowercase hex digits
  std::uint64_t size = 0;
  friend bool operator==(const Digest&, const Digest&) = default;
};

// Streams the file through SHA-256 (256 KiB reads, one reused buffer per thread). nullopt if it cannot be
// read.
std::optional<Digest> digest_file(const std::filesystem::path& path);
Digest digest_bytes(std::string_view bytes);

bool is_hex_digest(std::string_view s);

}  // namespace sylva
