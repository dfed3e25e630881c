# Importing YADE leaves no folder in $TMPDIR or /tmp (yade_import_tmp.py says which and why).
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade)
  add_test(NAME yade_import_leaves_no_temp
    COMMAND sh -c "t=$(mktemp -d) && TMPDIR=$t /usr/bin/python3 \"$1\" \"$2\"; rc=$?; rm -rf $t; exit $rc"
            sh ${CMAKE_CURRENT_LIST_DIR}/yade_import_tmp.py ${PROJECT_SOURCE_DIR}/dem_app/python)
  set_tests_properties(yade_import_leaves_no_temp PROPERTIES TIMEOUT 120
    LABELS "integration;no_asan")
endif()
