# scripts/aspect_ratio_study (issue 14, item 9), smoke test: one tiny scene (a = 1, shipped
# transfer, no cfl check); the study itself is too slow for CI (docs/column_collapse.md).
add_test(NAME aspect_ratio_study_smoke COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/aspect_ratio_study.sh)
set_tests_properties(aspect_ratio_study_smoke PROPERTIES TIMEOUT 120 LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}")
