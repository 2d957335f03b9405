# Shared part of the bundled-case CTests (label `cases`), included by each tests/cases/<case>.cmake:
# runs `sphforge run CASE --out OUT` (OUT is a folder inside the build tree, owned by the test) and
# reads summary.json into `summary`, `status`, `ratio` (kinetic_to_work_ratio_max) and `wall`.
# Invoked as: cmake -DSPHFORGE=... -DCASE=... -DOUT=... [-DEXTRA_ARGS="--set|key=value|..."] -P <case>.cmake
# (EXTRA_ARGS: more arguments of `sphforge run`, separated by |).
file(REMOVE_RECURSE "${OUT}")
set(extra_args "")
if(DEFINED EXTRA_ARGS)
  string(REPLACE "|" ";" extra_args "${EXTRA_ARGS}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" -E env OMP_WAIT_POLICY=PASSIVE "${SPHFORGE}" run "${CASE}" --out "${OUT}" --quiet
                        ${extra_args}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sphforge run ${CASE} exited with ${rc}")
endif()
file(READ "${OUT}/summary.json" summary)
string(JSON status GET "${summary}" status)
string(JSON ratio GET "${summary}" kinetic_to_work_ratio_max)
string(JSON wall GET "${summary}" wall_time_s)

# The metric `key` of summary.json into `var`.
macro(case_metric var key)
  string(JSON ${var} GET "${summary}" metrics ${key})
endmacro()

# Fails unless the run ended with `expected` (completed, process_finished, ...).
function(expect_status expected why)
  if(NOT status STREQUAL "${expected}")
    message(FATAL_ERROR "status is '${status}', expected '${expected}' (${why})")
  endif()
endfunction()

# Quasi-static: kinetic energy below 10 % of the ram's work (the paper's rule of thumb for mass
# scaling); a growing numerical oscillation would break it first.
function(expect_quasi_static)
  if(ratio GREATER 0.1)
    message(FATAL_ERROR "kinetic/work ratio ${ratio} > 0.1: not quasi-static or unstable")
  endif()
endfunction()

# A ram-extrusion sector: the process's sector count must equal the core's symmetry multiplier, or the
# ram force, summed over the sector's particles, is wrongly scaled to the full body (eq. 70).
function(expect_sector_count_matches_symmetry)
  string(JSON sectors GET "${summary}" metrics sector_count)
  string(JSON multiplier GET "${summary}" symmetry multiplier)
  if(NOT sectors EQUAL multiplier)
    message(FATAL_ERROR "process.sector_count ${sectors} differs from the symmetry multiplier ${multiplier}")
  endif()
endfunction()

# A die with a land: material passed the whole land, at least a sector's share of a particle layer
# (5 particles) below its exit.
function(expect_land_passed extruded)
  if(extruded LESS 5)
    message(FATAL_ERROR "the land was not passed: ${extruded} particles below its exit")
  endif()
endfunction()

# Fails when `value` is below the physical lower bound `bound` (named by `what`).
function(expect_at_least value bound what)
  if(value LESS bound)
    message(FATAL_ERROR "${what} ${value} is below ${bound}")
  endif()
endfunction()

# Thermal bounds of a rotating-tool case (friction extrusion, FSBE): friction heats the interface above
# room temperature `t_room`, and stays below the Johnson-Cook melting temperature `t_melt` (the material
# has no strength there, so the Tresca friction heat vanishes); the tool thermocouple is heated only by
# conduction from the billet, so it lies between room temperature and the interface.
function(expect_interface_and_tool_temperatures t_if t_tool t_room t_melt)
  if(NOT (t_if GREATER 300 AND t_if LESS t_melt))
    message(FATAL_ERROR "interface temperature ${t_if} K outside (300 K, ${t_melt} K)")
  endif()
  if(NOT (t_tool GREATER t_room AND t_tool LESS t_if))
    message(FATAL_ERROR "tool thermocouple ${t_tool} K not between room temperature ${t_room} K and the interface ${t_if} K")
  endif()
endfunction()

# Regression against a stored reference (the JSON text `reference`, e.g. reference/quick_metrics.json):
# each metric named after it inside [min, max] of its entry, whose `why` states the reason for the width
# (CMake compares floats but has no float arithmetic, so the bounds are stored, not computed).
function(expect_reference_ranges reference)
  foreach(key ${ARGN})
    string(JSON value GET "${summary}" metrics ${key})
    string(JSON lo GET "${reference}" metrics ${key} min)
    string(JSON hi GET "${reference}" metrics ${key} max)
    string(JSON why GET "${reference}" metrics ${key} why)
    message(STATUS "${key} = ${value}, reference range [${lo}, ${hi}] (${why})")
    if(value LESS lo OR value GREATER hi)
      message(FATAL_ERROR "${key} = ${value} outside the reference range [${lo}, ${hi}]")
    endif()
  endforeach()
endfunction()
