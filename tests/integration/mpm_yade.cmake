# mpm_app against 2 YADE server ranks on a tiny scene (issue 3, item 9). Normal pass only (CI
# time): the YADE backend C++ runs under ASan in the YadeBackend units, the remote provider in
# the coupling_client_* tests.
mpmdem_test(NAME mpm_yade_block_2ranks NEEDS yade COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/mpm_block.sh yade
            TIMEOUT 300 LABELS integration no_asan SERIAL)
