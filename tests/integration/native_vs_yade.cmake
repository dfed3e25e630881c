# Native vs YADE backend on one packing and one seeded dF sequence (issue 15, item 2; the
# tolerances in native_vs_yade.py). The YADE side runs as a Python module: no YADE backend
# build needed, only Debian's yade.
mpmdem_test(NAME native_vs_yade NEEDS yade-module COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/native_vs_yade.sh
            TIMEOUT 120 LABELS integration no_asan)
# The same with the frict_visco law (e_n 0.5; tolerances in native_vs_yade.py).
mpmdem_test(NAME native_vs_yade_visco NEEDS yade-module
            COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/native_vs_yade.sh 0.5
            TIMEOUT 120 LABELS integration no_asan)
