# SPDX-License-Identifier: MIT
# expect_run for the `xrsc` command-line tests (cmake -P scripts; include after setting
# XRSC_EXE and `failures`): runs XRSC_EXE with ARGS, checks its exit status and, when given,
# that stdout / stderr match a regex or stderr does not; prints "[ ok ] NAME" or "FAIL NAME:
# why", counting failures in the caller's `failures`.
# expect_run(NAME name EXIT code [STDOUT regex] [STDERR regex] [NOT_STDERR regex] ARGS ...)
function(expect_run)
  cmake_parse_arguments(E "" "NAME;EXIT;STDOUT;STDERR;NOT_STDERR" "ARGS" ${ARGN})
  execute_process(COMMAND ${XRSC_EXE} ${E_ARGS}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  set(ok TRUE)
  if(NOT rc STREQUAL E_EXIT)
    set(ok FALSE)
    message("FAIL ${E_NAME}: exit ${rc}, expected ${E_EXIT}\n  stdout: ${out}\n  stderr: ${err}")
  endif()
  if(DEFINED E_STDOUT AND NOT out MATCHES "${E_STDOUT}")
    set(ok FALSE)
    message("FAIL ${E_NAME}: stdout does not match '${E_STDOUT}':\n${out}")
  endif()
  if(DEFINED E_STDERR AND NOT err MATCHES "${E_STDERR}")
    set(ok FALSE)
    message("FAIL ${E_NAME}: stderr does not match '${E_STDERR}':\n${err}")
  endif()
  if(DEFINED E_NOT_STDERR AND err MATCHES "${E_NOT_STDERR}")
    set(ok FALSE)
    message("FAIL ${E_NAME}: stderr matches '${E_NOT_STDERR}':\n${err}")
  endif()
  if(ok)
    message("[ ok ] ${E_NAME}")
  else()
    math(EXPR f "${failures} + 1")
    set(failures ${f} PARENT_SCOPE)
  endif()
endfunction()
