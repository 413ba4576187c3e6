# Writes OUT (isg_version.h): the commit the source tree is at, for
# `isg --version`. Run at every build (CMakeLists.txt's isg_version target); the header is
# rewritten only when its text changes, so an unchanged commit rebuilds nothing.
# -DSRC=<source tree> -DOUT=<header>
set(commit "unknown")
find_package(Git QUIET)
if(GIT_FOUND AND EXISTS "${SRC}/.git")
  execute_process(COMMAND ${GIT_EXECUTABLE} -C "${SRC}" rev-parse --short=12 HEAD
                  OUTPUT_VARIABLE c RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(rc EQUAL 0)
    set(commit "${c}")
    execute_process(COMMAND ${GIT_EXECUTABLE} -C "${SRC}" diff --quiet HEAD --
                    RESULT_VARIABLE dirty OUTPUT_QUIET ERROR_QUIET)
    if(NOT dirty EQUAL 0)
      string(APPEND commit "-modified")
    endif()
  endif()
endif()
set(text "#pragma once\n#define ISG_COMMIT \"${commit}\"\n")
set(old "")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()
