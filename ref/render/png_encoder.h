// PNG encoding of an RGB8 canvas by OpenImageIO, in the module plugins/oiio_png.cpp (loaded at the
// first call, core/modules.h).
#pragma once
#include <cstdint>
#include <string>

namespace dynref::render {

// The PNG bytes of `rgb` (width * height * 3 bytes). `name` names the file for messages and for
// OpenImageIO. Throws std::runtime_error when the module cannot be loaded (naming every place
// looked in) or the encoder fails.
std::string EncodePngRgb8(const uint8_t* rgb, int width, int height, const std::string& name);

}  // namespace dynref::render
