# CTest (label `cases`): the bundled default case runs to its end, stays stable and extrudes.
include(${CMAKE_CURRENT_LIST_DIR}/run_case.cmake)
case_metric(extruded extruded_particles)
case_metric(length extrudate_length_m)
case_metric(peak peak_extrusion_pressure_Pa)
message(STATUS "status ${status}, extruded particles ${extruded}, extrudate ${length} m, peak P_ex ${peak} Pa, "
               "max kinetic/work ${ratio}, wall ${wall} s")
expect_status(completed "the run reaches run.end_time")
# Material must leave the orifice: at least a few particle layers' worth (3 mm) of extrudate.
if(extruded LESS 20 OR length LESS 0.003)
  message(FATAL_ERROR "too little extrusion: ${extruded} particles, ${length} m")
endif()
expect_quasi_static()
# Lower bound: no extrusion below the ideal homogeneous work, 2 sigma_y ln(D0/D) = 1.61 MPa.
expect_at_least(${peak} 1.61e6 "peak extrusion pressure (Pa), ideal-work lower bound")
