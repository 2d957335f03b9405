# Shared part of the validation CTests (label `validation`, full bundled cases, never in CI): each
# check records a failure instead of stopping, so one run reports every item of its issue; the
# script fails at the end if any item failed. Included after run_case.cmake.
set(validation_failures "")

# Records `what` as failed unless lo <= value <= hi (CMake compares floating-point numbers).
macro(check_between what value lo hi)
  if(${value} LESS ${lo} OR ${value} GREATER ${hi})
    message(STATUS "NOT MET: ${what} = ${${value}} outside [${lo}, ${hi}]")
    list(APPEND validation_failures "${what}")
  else()
    message(STATUS "met: ${what} = ${${value}} in [${lo}, ${hi}]")
  endif()
endmacro()

# Records `what` as failed unless a < b.
macro(check_less what a b)
  if(NOT ${a} LESS ${b})
    message(STATUS "NOT MET: ${what}: ${${a}} is not below ${${b}}")
    list(APPEND validation_failures "${what}")
  else()
    message(STATUS "met: ${what}: ${${a}} < ${${b}}")
  endif()
endmacro()

macro(finish_validation)
  list(LENGTH validation_failures n_failed)
  if(n_failed GREATER 0)
    message(FATAL_ERROR "${n_failed} validation item(s) not met: ${validation_failures}")
  endif()
endmacro()
