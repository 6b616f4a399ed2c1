// Compact data files of `dynref view` (README.md "Size"): a frame's records as columns (one per
// record schema and field, file order kept by a schema-id column), numbers rounded to the
// significant digits the page shows, repeated columns and id-like text columns encoded compactly
// (PackColumns), compressed (LZMA; zlib kept for tests and comparisons) into a <script> string of
// one character per byte (the page loads the file as windows-1252 and decodes the bytes with
// site/lzma.js: no fetch(), works from file://).
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace dynref::view {

// zlib (RFC 1950) stream of `text` at level 9 as the body of a JavaScript "..." literal, one
// character per byte: a file holding it is loaded as windows-1252 (<script charset>; every byte is
// one code point there and the page maps it back), `"`, `\`, LF and CR written as JavaScript
// escapes and NUL as \x00: ~2 % overhead against basE91's 23 % (README.md "Size").
std::string DeflateLatin1(const std::string& text);
// Inverse of DeflateLatin1 (tests); InputError on a corrupt string.
std::string InflateLatin1(const std::string& literal);
// The same literal of an LZMA stream (liblzma's ".lzma" format: 13-byte header, LZMA1 at preset
// 9e with pb = 0, end marker) of `text`: frame chunks and the summary, 25-30 % smaller than zlib
// (README.md "Size"); the page decodes it with site/lzma.js. UnlzmaLatin1 inverts it (tests).
std::string LzmaLatin1(const std::string& text);
std::string UnlzmaLatin1(const std::string& literal);
// `bytes` as a JavaScript "..." literal body, one character per byte, and back (InputError).
std::string Latin1Literal(const std::string& bytes);
std::string Latin1Bytes(const std::string& literal);
// A frame's columns {schema id: [column...]} (site_data.cpp FrameColumns) with each column that
// equals an earlier one (in the object's key order) replaced by {"=": [schema id, index]}, and each
// remaining all-text column whose values share one text between their integers ("f12.3",
// "mp4@kf2", "-1") by {"c": count, "t": [texts], "n": [[first, deltas...] per integer]}. The page
// (site/view.js expandColumns) restores the plain columns; UnpackColumns is its C++ twin (tests).
nlohmann::json PackColumns(const nlohmann::json& cols);
nlohmann::json UnpackColumns(const nlohmann::json& packed);
// A number for the page: `digits` significant digits (17: exact), integral values as integers,
// non-finite values as the strings the trace dump uses ("nan", "inf", "-inf").
nlohmann::json RoundedNumber(double v, int digits);

}  // namespace dynref::view
