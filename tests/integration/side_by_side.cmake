# Side by side (issue 3, item 7): dem_app --backend yade over MPI (2 ranks, driven by
# element_test --test df_file) against a standalone one-process YADE script on the same
# 40-sphere packing and dF sequence: equal stresses to <= 1e-10 relative.
mpmdem_test(NAME side_by_side_yade_standalone NEEDS yade COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/side_by_side.sh
            TIMEOUT 180 LABELS integration no_asan SERIAL)
