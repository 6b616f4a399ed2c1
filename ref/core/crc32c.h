// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78, init and final xor 0xFFFFFFFF), the
// checksum of trace blocks (ref/trace/README.md, schema 2). Check value: Crc32c("123456789")
// == 0xE3069283 (RFC 3720 appendix B.4). Software slicing-by-8, no CPU-specific instructions,
// so every machine computes the same value at the same speed class (~1-2 GB/s).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace dynref {

// Running checksum: Crc32cExtend(Crc32cExtend(0, a), b) == Crc32c(a + b).
uint32_t Crc32cExtend(uint32_t crc, const void* data, size_t size);
inline uint32_t Crc32c(const void* data, size_t size) { return Crc32cExtend(0, data, size); }
inline uint32_t Crc32c(const std::string& bytes) { return Crc32c(bytes.data(), bytes.size()); }

}  // namespace dynref
