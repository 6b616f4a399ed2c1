// SHA-256 (FIPS 180-4) for content hashes of inputs, models and traces.
#pragma once
#include <cstdint>
#include <string>

namespace dynref {

class Sha256 {
 public:
  Sha256();
  void Update(const void* data, size_t size);
  std::string HexDigest();  // finalises; call once

 private:
  void Block(const unsigned char* p);
  uint32_t h_[8];
  unsigned char buf_[64];
  size_t buf_len_ = 0;
  uint64_t total_ = 0;
};

std::string Sha256Hex(const std::string& bytes);
// Hash of a file's bytes; throws InputError naming the file when it cannot be read.
std::string Sha256File(const std::string& path);

}  // namespace dynref
