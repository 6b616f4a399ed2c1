// The default vocabulary (models/vocab/, README there): the file's bytes are assembled into the
// library with .incbin (GNU as), so no file is read or downloaded at run time.
#include "core/error.h"
#include "place/vocabulary.h"

#ifdef DYNREF_DEFAULT_VOCABULARY_PATH
__asm__(
    ".pushsection .rodata\n"
    ".balign 16\n"
    ".global dynref_place_default_vocabulary_begin\n"
    "dynref_place_default_vocabulary_begin:\n"
    ".incbin \"" DYNREF_DEFAULT_VOCABULARY_PATH "\"\n"
    ".global dynref_place_default_vocabulary_end\n"
    "dynref_place_default_vocabulary_end:\n"
    ".byte 0\n"
    ".popsection\n");
extern "C" const char dynref_place_default_vocabulary_begin[];
extern "C" const char dynref_place_default_vocabulary_end[];
#endif

namespace dynref::place {

const Vocabulary& Vocabulary::Default() {
#ifdef DYNREF_DEFAULT_VOCABULARY_PATH
  static const Vocabulary v = ParseDynref(
      std::string(dynref_place_default_vocabulary_begin,
                  dynref_place_default_vocabulary_end - dynref_place_default_vocabulary_begin),
      "<embedded " DYNREF_DEFAULT_VOCABULARY_NAME ">");
  return v;
#else
  throw InputError("backbone.vocabulary", "this build has no embedded default vocabulary (models/vocab/ missing)");
#endif
}

}  // namespace dynref::place
