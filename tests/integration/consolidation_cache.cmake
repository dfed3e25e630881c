# Consolidation once per (packing, stress), and its cache on disk reused by a second run with
# the same results (issue 36, item 5).
mpmdem_test(NAME consolidation_cache COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/consolidation_cache.sh
            TIMEOUT 120 LABELS integration no_asan SERIAL)
