# scripts/grid_convergence_study (issue 14, item 4), smoke test on the two coarsest grids; the
# full study (three cell sizes, 2 and 3 points per cell) takes ~7 min (docs/transfers.md).
add_test(NAME grid_convergence_study_smoke
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/grid_convergence_study.sh)
set_tests_properties(grid_convergence_study_smoke PROPERTIES TIMEOUT 180
  LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}")
