# CTest (label `cases`): a bundled dry-ice quick case runs to its end, stays quasi-static, extrudes,
# and its peak ram force F_L (max of history ram_force_N) lies above the ideal-work lower bound.
# Invoked as: cmake -DSPHFORGE=... -DCASE=... -DOUT=... -P dry_ice_quick.cmake
file(REMOVE_RECURSE "${OUT}")  # OUT is a folder inside the build tree, owned by this test
execute_process(COMMAND "${CMAKE_COMMAND}" -E env OMP_WAIT_POLICY=PASSIVE "${SPHFORGE}" run "${CASE}" --out "${OUT}" --quiet
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sphforge run ${CASE} exited with ${rc}")
endif()
file(READ "${OUT}/summary.json" summary)
string(JSON status GET "${summary}" status)
string(JSON extruded GET "${summary}" metrics extruded_particles)
string(JSON ratio GET "${summary}" kinetic_to_work_ratio_max)
string(JSON wall GET "${summary}" wall_time_s)
# F_L: the largest ram force over the stroke, read from history.csv (column ram_force_N).
file(STRINGS "${OUT}/history.csv" lines)
list(GET lines 0 header)
string(REPLACE "," ";" columns "${header}")
list(FIND columns "ram_force_N" col)
if(col LESS 0)
  message(FATAL_ERROR "history.csv has no ram_force_N column")
endif()
list(REMOVE_AT lines 0)
set(peak 0)
set(peak_row "")
foreach(line IN LISTS lines)
  string(REPLACE "," ";" values "${line}")
  list(GET values ${col} f)
  if(f GREATER peak)
    set(peak ${f})
    set(peak_row "${line}")
  endif()
endforeach()
message(STATUS "status ${status}, extruded particles ${extruded}, F_L ${peak} N, max kinetic/work ${ratio}, wall ${wall} s")
if(NOT status STREQUAL "completed")
  message(FATAL_ERROR "status is '${status}', expected 'completed'")
endif()
# Material must leave the die (the cavity is full at the start, so any ram travel extrudes).
if(extruded LESS 1)
  message(FATAL_ERROR "nothing extruded")
endif()
# Quasi-static: kinetic energy below 10 % of the ram's work (the rule of thumb for mass scaling).
if(ratio GREATER 0.1)
  message(FATAL_ERROR "kinetic/work ratio ${ratio} > 0.1: not quasi-static or unstable")
endif()
# Lower bound: no extrusion below the ideal homogeneous work through the die,
# F = 2 sigma_y ln(D/d) pi D^2/4 = 2 (3.5 MPa) ln(28/16) pi (14 mm)^2 = 2412 N (docs/validation/dry_ice.md).
if(peak LESS 2412)
  message(FATAL_ERROR "F_L ${peak} N is below the ideal-work lower bound 2412 N")
endif()
