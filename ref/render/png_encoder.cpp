#include "render/png_encoder.h"

#include <cstdlib>
#include <memory>
#include <stdexcept>

#include "core/modules.h"
#include "plugins/oiio_png_abi.h"

namespace dynref::render {

std::string EncodePngRgb8(const uint8_t* rgb, int width, int height, const std::string& name) {
  static const auto encode =  // looked up once per process, like plugins::OpenCvExtraModule()
      reinterpret_cast<DynrefEncodePngFn>(ModuleSymbol(DYNREF_OIIO_PNG_MODULE, DYNREF_ENCODE_PNG_SYMBOL));
  unsigned char* out = nullptr;
  size_t size = 0;
  char error[512] = {0};
  if (encode(rgb, width, height, name.c_str(), &out, &size, error, sizeof error) != 0)
    throw std::runtime_error("cannot encode " + name + ": " + error);
  const std::unique_ptr<unsigned char, decltype(&std::free)> owned(out, &std::free);
  return std::string(reinterpret_cast<const char*>(out), size);
}

}  // namespace dynref::render
