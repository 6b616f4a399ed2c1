// Lossless, locale-independent number formatting for every text output.
#pragma once
#include <string>

namespace dynref {

// Shortest text that parses back to the same double ("%.17g"; "nan"/"inf" spelled out).
std::string FormatDouble17(double v);
// Fixed decimals, e.g. FormatFixed(0.0081437, 6) == "0.008144".
std::string FormatFixed(double v, int decimals);

}  // namespace dynref
