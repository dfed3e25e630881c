# Lazy RVE evaluation (issue 6, item 2) on the tiny YADE column, with an exact resume.
mpmdem_test(NAME lazy_yade_column NEEDS yade COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/lazy.sh
            TIMEOUT 600 LABELS integration no_asan SERIAL)
