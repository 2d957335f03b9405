# Stress run (label `stress`): the quick land die (L/D = 10/3, 90 deg sector) pushed to a 2 mm stroke,
# 2.5 times the bundled 0.8 mm, with density diffusion (theory eq. 4a; EXTRA_ARGS sets the stroke and
# the delta). Without it the continuity equation's density drift near the ram's centre (layers of
# -15 % and +15 %) blew the axis particle up at u = 1.92 mm (exit 3, docs/stability.md); the run must
# now reach the end of its stroke and stay quasi-static. One thread (the test's environment): the same
# sums on every machine.
include(${CMAKE_CURRENT_LIST_DIR}/run_case.cmake)
case_metric(steady steady_extrusion_pressure_Pa)
case_metric(scatter steady_extrusion_pressure_scatter_Pa)
message(STATUS "status ${status}, steady P_ex ${steady} Pa +- ${scatter} Pa (window 1.4-2.0 mm), "
               "max kinetic/work ${ratio}, wall ${wall} s")
expect_status(process_finished "the 2 mm stroke reached")
expect_quasi_static()
