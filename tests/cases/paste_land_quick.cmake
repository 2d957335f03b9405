# CTest (label `cases`): the quick square-entry land die (L/D = 10/3, Navier slip on barrel and die,
# 90 deg sector) runs to its end, fills the land, extrudes, stays quasi-static, and its steady P_ex
# is at least the lower bound of an orifice plus a land (eq. 77 of docs/theory.md).
include(${CMAKE_CURRENT_LIST_DIR}/run_case.cmake)
case_metric(extruded extruded_particles)
case_metric(length extrudate_length_m)
case_metric(steady steady_extrusion_pressure_Pa)
case_metric(scatter steady_extrusion_pressure_scatter_Pa)
case_metric(peak_force peak_force_N)
message(STATUS "status ${status}, extruded particles (below the land exit) ${extruded}, extrudate ${length} m, "
               "steady P_ex ${steady} Pa +- ${scatter} Pa, peak force ${peak_force} N, max kinetic/work ${ratio}, "
               "wall ${wall} s")
# The run ends when the ram has travelled the stroke (the process's end), before run.end_time.
expect_status(process_finished "the stroke reached")
expect_sector_count_matches_symmetry()
# Material must have passed the whole 10 mm land: some particles (a sector's share of a layer)
# below its exit.
expect_land_passed(${extruded})
expect_quasi_static()
# Lower bound (eq. 77): ideal work of the area reduction, 2 sigma_y ln(D0/D) = 1.61 MPa, plus the
# land's wall yield stress alone, 4 (L/D) tau_0 = 0.24 MPa: 1.85 MPa.
expect_at_least(${steady} 1.85e6 "steady P_ex (Pa), lower bound of orifice plus land")
