// Compact data files of `dynref view` (README.md "Size"): a frame's records as columns (one per
// record schema and field, file order kept by a schema-id column), numbers rounded to the
// significant digits the page shows, zlib-compressed and base64-encoded into a <script> string
// (the page inflates it with the browser's DecompressionStream: no fetch(), works from file://).
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace dynref::view {

// zlib (RFC 1950) stream of `text` at level 9, as base64 (RFC 4648, padded).
std::string DeflateBase64(const std::string& text);
// Inverse of DeflateBase64 (tests); InputError on a corrupt string.
std::string InflateBase64(const std::string& b64);
// A number for the page: `digits` significant digits (17: exact), integral values as integers,
// non-finite values as the strings the trace dump uses ("nan", "inf", "-inf").
nlohmann::json RoundedNumber(double v, int digits);

}  // namespace dynref::view
