# Script mode (cmake -DSOURCE_DIR=... -DOUTPUT=... -P build_sha.cmake), run at every build: writes OUTPUT, a header
# defining DEFORMBENCH_BUILD_SHA as the source tree's short commit ("+dirty" with uncommitted changes to tracked
# files; "unknown" outside a git checkout), and touches it only when that changed, so that an unchanged commit
# recompiles nothing. core/provenance reports it: a binary names the commit it was compiled from, not whatever
# the tree holds when it runs.
execute_process(COMMAND git -C "${SOURCE_DIR}" rev-parse --short=12 HEAD
  OUTPUT_VARIABLE sha OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE failed)
if(failed OR sha STREQUAL "")
  set(sha "unknown")
else()
  execute_process(COMMAND git -C "${SOURCE_DIR}" status --porcelain --untracked-files=no
    OUTPUT_VARIABLE changes OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT changes STREQUAL "")
    string(APPEND sha "+dirty")
  endif()
endif()
set(text "#define DEFORMBENCH_BUILD_SHA \"${sha}\"\n")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()
