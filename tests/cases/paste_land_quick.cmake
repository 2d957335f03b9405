# CTest (label `cases`): the quick square-entry land die (L/D = 10/3, Navier slip on barrel and die,
# 90 deg sector) runs to its end, fills the land, extrudes, stays quasi-static, and its steady P_ex
# is at least the lower bound of an orifice plus a land (eq. 77 of docs/theory.md).
# Invoked as: cmake -DSPHFORGE=... -DCASE=... -DOUT=... -P paste_land_quick.cmake
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
string(JSON steady GET "${summary}" metrics steady_extrusion_pressure_Pa)
string(JSON scatter GET "${summary}" metrics steady_extrusion_pressure_scatter_Pa)
string(JSON peak_force GET "${summary}" metrics peak_force_N)
string(JSON sectors GET "${summary}" metrics sector_count)
string(JSON multiplier GET "${summary}" symmetry multiplier)
string(JSON ratio GET "${summary}" kinetic_to_work_ratio_max)
string(JSON wall GET "${summary}" wall_time_s)
message(STATUS "status ${status}, extruded particles (below the land exit) ${extruded}, extrudate ${length} m, "
               "steady P_ex ${steady} Pa +- ${scatter} Pa, peak force ${peak_force} N, max kinetic/work ${ratio}, "
               "wall ${wall} s")
# The run ends when the ram has travelled the stroke (the process's end), before run.end_time.
if(NOT status STREQUAL "process_finished")
  message(FATAL_ERROR "status is '${status}', expected 'process_finished' (the stroke reached)")
endif()
# The process's sector count must be the core's multiplier, or the ram force is wrongly scaled (eq. 70).
if(NOT sectors EQUAL multiplier)
  message(FATAL_ERROR "process.sector_count ${sectors} differs from the symmetry multiplier ${multiplier}")
endif()
# Material must have passed the whole 10 mm land: some particles (a sector's share of a layer)
# below its exit.
if(extruded LESS 5)
  message(FATAL_ERROR "the land was not passed: ${extruded} particles below its exit")
endif()
# Quasi-static: kinetic energy below 10 % of the ram's work (the paper's rule of thumb for mass scaling).
if(ratio GREATER 0.1)
  message(FATAL_ERROR "kinetic/work ratio ${ratio} > 0.1: not quasi-static or unstable")
endif()
# Lower bound (eq. 77): ideal work of the area reduction, 2 sigma_y ln(D0/D) = 1.61 MPa, plus the
# land's wall yield stress alone, 4 (L/D) tau_0 = 0.24 MPa: 1.85 MPa.
if(steady LESS 1.85e6)
  message(FATAL_ERROR "steady P_ex ${steady} Pa is below the lower bound 1.85 MPa")
endif()
