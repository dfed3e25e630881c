# Strong-scaling study, cost model and Amdahl fit (issue 5, items 2-3).
add_test(NAME scaling_study_elastic COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/scaling.sh)
set_tests_properties(scaling_study_elastic PROPERTIES TIMEOUT 300 LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}" RUN_SERIAL TRUE)
