// LzmaLatin1 / UnlzmaLatin1 (packed.h): frame data as an LZMA stream in a one-character-per-byte
// literal. The page's decoder is site/lzma.js (the browser has no LZMA).
#include <lzma.h>

#include <stdexcept>

#include "core/error.h"
#include "view/packed.h"

namespace dynref::view {
namespace {

// Runs `z` over `in` to the end of the stream; false when liblzma reports an error.
bool RunLzma(lzma_stream* z, const std::string& in, std::string* out) {
  z->next_in = reinterpret_cast<const uint8_t*>(in.data());
  z->avail_in = in.size();
  uint8_t buf[65536];
  lzma_ret rc = LZMA_OK;
  while (rc == LZMA_OK) {
    z->next_out = buf;
    z->avail_out = sizeof(buf);
    rc = lzma_code(z, LZMA_FINISH);
    out->append(reinterpret_cast<const char*>(buf), sizeof(buf) - z->avail_out);
  }
  lzma_end(z);
  return rc == LZMA_STREAM_END;
}

}  // namespace

std::string LzmaLatin1(const std::string& text) {
  lzma_options_lzma o;
  if (lzma_lzma_preset(&o, 9 | LZMA_PRESET_EXTREME)) throw std::runtime_error("lzma preset failed");
  // The dictionary only needs to hold the text (the page's decoder keeps the whole output anyway).
  uint32_t dict = 4096;
  while (dict < text.size() && dict < (1u << 26)) dict *= 2;
  o.dict_size = dict;
  o.pb = 0;  // text: no 4-byte alignment of positions (README.md "Size")
  lzma_stream z = LZMA_STREAM_INIT;
  if (lzma_alone_encoder(&z, &o) != LZMA_OK) throw std::runtime_error("lzma_alone_encoder failed");
  std::string bytes;
  if (!RunLzma(&z, text, &bytes)) throw std::runtime_error("lzma encoding failed");
  return Latin1Literal(bytes);
}

std::string UnlzmaLatin1(const std::string& literal) {
  lzma_stream z = LZMA_STREAM_INIT;
  if (lzma_alone_decoder(&z, UINT64_MAX) != LZMA_OK) throw std::runtime_error("lzma_alone_decoder failed");
  std::string out;
  if (!RunLzma(&z, Latin1Bytes(literal), &out)) throw InputError("view data", "not a complete LZMA stream");
  return out;
}

}  // namespace dynref::view
