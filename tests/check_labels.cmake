# Every test named in labels.cmake exists, so that no slow test loses its label silently
# (CTest ignores set_tests_properties on a name it does not know).
function(set_tests_properties)
endfunction()  # only the list is wanted from labels.cmake here
include(${LIST})
list(LENGTH PBXMPM_LABELLED_TESTS n)
math(EXPR last "${n} - 1")
foreach(i RANGE 1 ${last} 3)
  list(GET PBXMPM_LABELLED_TESTS ${i} test)
  math(EXPR m "${i} - 1")
  list(GET PBXMPM_LABELLED_TESTS ${m} module)
  if(module STREQUAL "distributed" AND NOT EXISTS ${BUILD}/tests/test_distributed)
    continue()  # built without MPI: that module has no tests
  endif()
  string(REPLACE "." "\\." re "${test}")
  execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --test-dir ${BUILD} -N -R "^${re}$" OUTPUT_VARIABLE out RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "Total Tests: 1\n")
    message(FATAL_ERROR "tests/labels.cmake names '${test}', which is not a test (renamed or removed?)")
  endif()
endforeach()
