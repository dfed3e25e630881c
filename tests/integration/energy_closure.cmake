# Issue 14, item 5: the local column's energy budget closes below 2 % with the APIC blend at a
# small velocity scale and a halved-twice time step (~15 s).
add_test(NAME energy_closure COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/energy_closure.sh)
set_tests_properties(energy_closure PROPERTIES TIMEOUT 180
  LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}")
