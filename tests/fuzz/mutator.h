// Blind, deterministic byte mutator for the fuzz driver (issue 20): stacked edits of the kinds
// that break text and binary parsers (bit flips, boundary bytes, number tokens, deleted,
// duplicated and swapped spans, truncation). Seeded by our own Rng, so run N of seed S is the
// same input on every machine and a finding replays from (target, seed, execution index).
#pragma once
#include <string>

#include "core/rng.h"

namespace dynref::fuzz {

std::string Mutate(const std::string& seed, Rng& rng);

}  // namespace dynref::fuzz
