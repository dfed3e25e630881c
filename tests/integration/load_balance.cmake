# Load balance with RVE migration (issue 5, item 4) and node-partition hostfiles (item 5).
set(_lb ${CMAKE_CURRENT_LIST_DIR}/load_balance.sh)
add_test(NAME load_balance_elastic COMMAND bash ${_lb} elastic)
set_tests_properties(load_balance_elastic PROPERTIES TIMEOUT 300 LABELS integration
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}" RUN_SERIAL TRUE)
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME load_balance_yade COMMAND bash ${_lb} yade)
  set_tests_properties(load_balance_yade PROPERTIES TIMEOUT 600 LABELS "integration;no_asan"
    ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
    RUN_SERIAL TRUE)
endif()
