# The local column with mu(I) as shipped (issue 14, item 5: E_err < 2 %) against the same
# scene without mu(I) on 0.055 m cells, side by side (~90 s on 2 cores).
add_test(NAME mu_i_column COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/mu_i_column.sh)
set_tests_properties(mu_i_column PROPERTIES TIMEOUT 600 PROCESSORS 2
  LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}")
