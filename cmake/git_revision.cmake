# Writes OUT (a header defining PBXMPM_GIT) from `git describe --always --dirty --tags` in SRC, at
# every build, and rewrites it only when the revision changed, so run.json and packing.json name
# the revision the binary was built from (a configure-time value went stale at the next commit).
execute_process(COMMAND git describe --always --dirty --tags
                WORKING_DIRECTORY ${SRC}
                OUTPUT_VARIABLE rev OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT rev)
  set(rev "unknown")
endif()
set(text "// generated at build time by cmake/git_revision.cmake\n#pragma once\n#define PBXMPM_GIT \"${rev}\"\n")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT "${old}" STREQUAL "${text}")
  file(WRITE ${OUT} "${text}")
endif()
