# The protocol's reference client (issue 37): a Python client written from docs/protocol.md
# alone drives dem_app --backend elastic, so that the doc and the code cannot drift apart.
# Included from tests/CMakeLists.txt.
mpmdem_test(NAME protocol_reference_client NEEDS mpi4py SERIAL TIMEOUT 120
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/reference_client.sh)
