# scripts/error_vs_runtime: error against run time (issue 6, item 1).
add_test(NAME error_vs_runtime_study COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/error_study.sh)
set_tests_properties(error_vs_runtime_study PROPERTIES TIMEOUT 300 LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}" RUN_SERIAL TRUE)
