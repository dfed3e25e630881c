# Two-process coupling tests (issue 2, item 8): each starts ompi-server, dem_app and a
# client through tests/integration/run_pair.sh, which kills every process it started.
# Included from tests/CMakeLists.txt.

# A stand-in client for mpm_app that checks every reply against the elastic law.
add_executable(rve_test_client ${CMAKE_CURRENT_LIST_DIR}/rve_test_client.cpp)
target_link_libraries(rve_test_client PRIVATE dem_server)

set(_pair ${CMAKE_CURRENT_LIST_DIR}/coupling_tests.sh)
set(_env "MPMDEM_BIN=${PROJECT_BINARY_DIR}" "MPMDEM_SRC=${PROJECT_SOURCE_DIR}")
foreach(_case
    client_elastic_1rank client_elastic_2ranks client_checkpoint_restore client_abort client_backend_error killed_client
    hash_mismatch version_mismatch no_server_client no_client_server
    mpm_no_server mpm_hash_mismatch swap_sides)
  add_test(NAME coupling_${_case} COMMAND bash ${_pair} ${_case})
  set_tests_properties(coupling_${_case} PROPERTIES TIMEOUT 120 LABELS integration
                       ENVIRONMENT "${_env}" RUN_SERIAL TRUE)
endforeach()
set_tests_properties(coupling_swap_sides PROPERTIES TIMEOUT 300)
