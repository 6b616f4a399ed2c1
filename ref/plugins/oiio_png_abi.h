// The C interface between render/png_encoder.cpp and the OpenImageIO module (oiio_png.cpp, built
// as the loadable dynref_oiio_png.so). OpenImageIO and the ~260 shared libraries it pulls in cost
// ~0.5 CPU-s at every process start; as a module only the processes that write a PNG pay it
// (core/modules.h).
#pragma once
#include <cstddef>

extern "C" {
// Encodes an RGB8 image (rows top to bottom, 3 bytes per pixel, no padding) as PNG in memory.
// `name` is the file name OpenImageIO is given (it picks the format from it). On success returns 0
// and sets *out (malloc'd; the caller frees it) and *out_size; on failure returns 1 and writes a
// message into `error` (error_size bytes, NUL-terminated).
typedef int (*DynrefEncodePngFn)(const unsigned char* rgb, int width, int height, const char* name,
                                 unsigned char** out, size_t* out_size, char* error,
                                 size_t error_size);
}

// The module's file and exported symbol.
#define DYNREF_OIIO_PNG_MODULE "dynref_oiio_png.so"
#define DYNREF_ENCODE_PNG_SYMBOL "dynref_encode_png"
