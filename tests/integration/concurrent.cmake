# Many runs at once (issue 16, item 4): two scripts/run of one scene started together from
# one checkout both finish, without port or run-directory collisions; the YADE case builds
# its packing library once.
add_test(NAME concurrent_runs_elastic COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/concurrent.sh elastic)
set_tests_properties(concurrent_runs_elastic PROPERTIES TIMEOUT 120 LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
  RUN_SERIAL TRUE)
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade AND EXISTS /usr/bin/python3.11-config)
  add_test(NAME concurrent_runs_yade COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/concurrent.sh yade)
  set_tests_properties(concurrent_runs_yade PROPERTIES TIMEOUT 180 LABELS "integration;no_asan"
    ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
    RUN_SERIAL TRUE)
endif()
