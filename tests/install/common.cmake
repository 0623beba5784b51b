# Shared by the install tests (cmake -P scripts): argument checks and a command runner that stops
# the test with the command's output.

# require(script VAR…): fail unless every VAR was given with -D.
function(require script)
  foreach(_var IN LISTS ARGN)
    if(NOT DEFINED ${_var})
      message(FATAL_ERROR "${script}: ${_var} not given")
    endif()
  endforeach()
endfunction()

# run(what COMMAND…): run the command; fail with its output unless it exits 0; its standard
# output is left in `out`.
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()
