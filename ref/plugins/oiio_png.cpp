// The loadable module that encodes overlay PNGs with OpenImageIO (oiio_png_abi.h says why it is a
// module). Same calls as the encoder had when it was linked in: an ImageBuf over the pixels,
// written through an in-memory IOVecOutput, so the PNG bytes are unchanged.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "plugins/oiio_png_abi.h"

namespace {

void CopyError(const std::string& message, char* error, size_t error_size) {
  if (error_size == 0) return;
  const size_t n = std::min(message.size(), error_size - 1);
  std::memcpy(error, message.data(), n);
  error[n] = '\0';
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int dynref_encode_png(
    const unsigned char* rgb, int width, int height, const char* name, unsigned char** out,
    size_t* out_size, char* error, size_t error_size) {
  try {
    OIIO::ImageBuf image(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::UINT8));
    const size_t n = static_cast<size_t>(width) * height * 3;
    if (n > 0 && !image.localpixels()) {
      CopyError("no pixel memory for a " + std::to_string(width) + "x" + std::to_string(height) +
                    " image", error, error_size);
      return 1;
    }
    if (n > 0) std::memcpy(image.localpixels(), rgb, n);
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput memory(bytes);
    image.set_write_ioproxy(&memory);
    if (!image.write(name, OIIO::TypeDesc::UINT8, "png")) {
      CopyError(image.geterror(), error, error_size);
      return 1;
    }
    *out = static_cast<unsigned char*>(std::malloc(bytes.empty() ? 1 : bytes.size()));
    if (!*out) {
      CopyError("out of memory", error, error_size);
      return 1;
    }
    if (!bytes.empty()) std::memcpy(*out, bytes.data(), bytes.size());
    *out_size = bytes.size();
    return 0;
  } catch (const std::exception& e) {
    CopyError(e.what(), error, error_size);
    return 1;
  }
}
