# CTest (label `cases`): a bundled dry-ice quick case runs to its end, stays quasi-static, extrudes,
# and its peak ram force F_L (metric peak_force_N) lies above the ideal-work lower bound.
include(${CMAKE_CURRENT_LIST_DIR}/run_case.cmake)
case_metric(extruded extruded_particles)
case_metric(peak peak_force_N)
message(STATUS "status ${status}, extruded particles ${extruded}, F_L ${peak} N, max kinetic/work ${ratio}, wall ${wall} s")
expect_status(completed "the run reaches run.end_time")
# The quick dry-ice cases are 90 deg sectors, like the paste quick cases.
expect_sector_count_matches_symmetry()
# Material must leave the die (the cavity is full at the start, so any ram travel extrudes).
if(extruded LESS 1)
  message(FATAL_ERROR "nothing extruded")
endif()
expect_quasi_static()
# Lower bound: no extrusion below the ideal homogeneous work through the die,
# F = 2 sigma_y ln(D/d) pi D^2/4 = 2 (3.5 MPa) ln(28/16) pi (14 mm)^2 = 2412 N (docs/validation/dry_ice.md).
expect_at_least(${peak} 2412 "F_L (N), ideal-work lower bound")
