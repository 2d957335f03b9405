# Validation (label `validation`, not in CI): the bundled friction-drilling case
# (cases/friction_drilling/hx220_m4.json, full 7.5 mm stroke) against the experiment (issue 9,
# cases/friction_drilling/reference/experiment_metrics.json): maximum axial force 639 N, maximum
# thermocouple temperature 445 C, total bushing length 4.34 mm, each within 5 %. The force history's
# shape (second peak near 5 s) is evaluated in docs/validation/friction_drilling.md.
include(${CMAKE_CURRENT_LIST_DIR}/run_case.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/validation_check.cmake)
expect_status(process_finished "the drill reaches the end of its stroke")
case_metric(force max_axial_force_N)
case_metric(probe max_probe_temperature_degC)
case_metric(bushing bushing_total_m)
check_between("maximum axial force (N), 639 N +- 5 %" force 607.05 670.95)
check_between("maximum thermocouple temperature (C), 445 C +- 5 %" probe 422.75 467.25)
check_between("total bushing length (m), 4.34 mm +- 5 %" bushing 0.004123 0.004557)
finish_validation()
