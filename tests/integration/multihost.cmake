# MPM and DEM on different hosts (issue 16, item 3): hosts A, B, C as network namespaces;
# A | B bitwise equal to the single-host run; B's link cut mid-run, then resumed on A | C.
# Needs root: otherwise skipped (multihost.sh exits 77).
mpmdem_test(NAME multihost_netns COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/multihost.sh
            TIMEOUT 180 LABELS integration no_asan SERIAL)
