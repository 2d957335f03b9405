# CTest (label `cases`): the bundled default case runs to its end, stays stable and extrudes.
# Invoked as: cmake -DSPHFORGE=... -DCASE=... -DOUT=... -P paste_orifice_quick.cmake
file(REMOVE_RECURSE "${OUT}")  # OUT is a folder inside the build tree, owned by this test
execute_process(COMMAND "${CMAKE_COMMAND}" -E env OMP_WAIT_POLICY=PASSIVE "${SPHFORGE}" run "${CASE}" --out "${OUT}" --quiet
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "sphforge run ${CASE} exited with ${rc}")
endif()
file(READ "${OUT}/summary.json" summary)
string(JSON status GET "${summary}" status)
string(JSON extruded GET "${summary}" metrics extruded_particles)
string(JSON length GET "${summary}" metrics extrudate_length_m)
string(JSON peak GET "${summary}" metrics peak_extrusion_pressure_Pa)
string(JSON ratio GET "${summary}" kinetic_to_work_ratio_max)
string(JSON wall GET "${summary}" wall_time_s)
message(STATUS "status ${status}, extruded particles ${extruded}, extrudate ${length} m, peak P_ex ${peak} Pa, "
               "max kinetic/work ${ratio}, wall ${wall} s")
if(NOT status STREQUAL "completed")
  message(FATAL_ERROR "status is '${status}', expected 'completed'")
endif()
# Material must leave the orifice: at least a few particle layers' worth (3 mm) of extrudate.
if(extruded LESS 20 OR length LESS 0.003)
  message(FATAL_ERROR "too little extrusion: ${extruded} particles, ${length} m")
endif()
# Quasi-static: kinetic energy below 10 % of the ram's work (the paper's rule of thumb for
# mass scaling); a growing numerical oscillation would break it first.
if(ratio GREATER 0.1)
  message(FATAL_ERROR "kinetic/work ratio ${ratio} > 0.1: not quasi-static or unstable")
endif()
# Lower bound: no extrusion below the ideal homogeneous work, 2 sigma_y ln(D0/D) = 1.61 MPa.
if(peak LESS 1.61e6)
  message(FATAL_ERROR "peak extrusion pressure ${peak} Pa is below the ideal-work lower bound 1.61 MPa")
endif()
