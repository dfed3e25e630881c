# Many runs at once (issue 16, item 4): two scripts/run of one scene started together from
# one checkout both finish, without port or run-directory collisions; the YADE case builds
# its packing library once.
mpmdem_test(NAME concurrent_runs_elastic COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/concurrent.sh elastic
            TIMEOUT 120 LABELS integration no_asan SERIAL)
mpmdem_test(NAME concurrent_runs_yade NEEDS yade COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/concurrent.sh yade
            TIMEOUT 180 LABELS integration no_asan SERIAL)
