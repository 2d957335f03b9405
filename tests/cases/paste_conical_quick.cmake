# CTest (label `cases`): the quick 45 deg conical-entry die (L/D = 12/3, Navier slip on barrel, cone and
# land, 90 deg sector) runs to the end of its stroke, extrudes through the land, stays quasi-static, and
# its steady P_ex is at least the lower bound of an area reduction plus a land (eq. 77 of docs/theory.md).
include(${CMAKE_CURRENT_LIST_DIR}/run_case.cmake)
case_metric(extruded extruded_particles)
case_metric(length extrudate_length_m)
case_metric(steady steady_extrusion_pressure_Pa)
case_metric(scatter steady_extrusion_pressure_scatter_Pa)
message(STATUS "status ${status}, extruded particles (below the land exit) ${extruded}, extrudate ${length} m, "
               "steady P_ex ${steady} Pa +- ${scatter} Pa, max kinetic/work ${ratio}, wall ${wall} s")
# The stroke (0.6 mm) ends the run before run.end_time (0.7 s at 1 mm/s).
expect_status(process_finished "the stroke reached")
expect_sector_count_matches_symmetry()
# The die cavity starts full (fill_die), so particles below the land exit are material pushed through
# the whole 12 mm land during the run; a sector's share of a layer at least.
expect_land_passed(${extruded})
expect_quasi_static()
# Lower bound (eq. 77): ideal work of the area reduction, 2 sigma_y ln(D0/D) = 1.61 MPa, plus the land's
# wall yield stress alone, 4 (L/D) tau_0 = 4 * 4 * 1.8e4 Pa = 0.29 MPa: 1.90 MPa. A sector whose ram
# force were not multiplied by the sector count would read a quarter of P_ex and fail here.
expect_at_least(${steady} 1.90e6 "steady P_ex (Pa), lower bound of area reduction plus land")
