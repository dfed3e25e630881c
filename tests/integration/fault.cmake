# Peer faults (issue 6, item 5): a DEM server rank killed mid-run; mpm_app names it, writes a
# fault checkpoint and exits 4 within a bound, nothing is left running, and
# scripts/run --resume reaches the same end state as an uninterrupted run.
add_test(NAME fault_killed_dem_rank
         COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/fault.sh elastic)
# Normal pass only (CI time): the C++ fault path runs under ASan in the PeerWatch units and
# coupling_killed_client.
set_tests_properties(fault_killed_dem_rank PROPERTIES TIMEOUT 180 LABELS "integration;no_asan"
  ENVIRONMENT "MPMDEM_BIN=${PROJECT_BINARY_DIR};MPMDEM_SRC=${PROJECT_SOURCE_DIR}"
  RUN_SERIAL TRUE)
