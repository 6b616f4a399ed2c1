# Run at every build (cmake -P): writes core/version.h with the current git commit, so traces,
# run.json and reports name the commit the binary was built from, not the one CMake was
# configured at. "+dirty" marks a build from a tree with uncommitted changes to tracked files.
# The file is only rewritten when its content changes (no needless recompiles).
# Inputs: -DSOURCE_DIR= -DOUTPUT= -DVERSION=
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SOURCE_DIR}
  OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT commit)
  set(commit "unknown")
else()
  execute_process(COMMAND git diff --quiet HEAD -- WORKING_DIRECTORY ${SOURCE_DIR}
    RESULT_VARIABLE dirty ERROR_QUIET)
  if(NOT dirty EQUAL 0)
    set(commit "${commit}+dirty")
  endif()
endif()
set(text "#pragma once\n#define DYNREF_VERSION \"${VERSION}\"\n#define DYNREF_GIT_COMMIT \"${commit}\"\n")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
else()
  set(old "")
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUTPUT} "${text}")
endif()
