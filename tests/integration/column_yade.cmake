# A minimal multiscale column collapse and its exact resume from a checkpoint (issue 4,
# items 6-7). Skipped (reported) where the YADE backend is not built.
mpmdem_test(NAME column_yade_tiny_resume NEEDS yade COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/column_yade.sh
            TIMEOUT 600 LABELS integration no_asan SERIAL)
