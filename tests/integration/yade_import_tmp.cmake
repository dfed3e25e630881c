# Importing YADE (dem_app/python/mpmdem_packing.py, _import_yade) leaves nothing in $TMPDIR:
# every YADE process used to leave a folder with a symlink there (194 after a day of tests).
# The import runs in a fresh TMPDIR, and YADE's O must answer after the folder is gone.
if(MPMDEM_WITH_YADE AND EXISTS /usr/bin/yade)
  add_test(NAME yade_import_leaves_no_temp
    COMMAND sh -c "t=$(mktemp -d) && TMPDIR=$t /usr/bin/python3 -c \"import sys; sys.path.insert(0, '$1'); import mpmdem_packing as pk; y = pk._import_yade(); import os; left = os.listdir('$t'); assert not left, left; y.O.reset(); assert y.O.iter == 0; print('no temp folder left; O answers')\"; rc=$?; rm -rf $t; exit $rc"
            sh ${PROJECT_SOURCE_DIR}/dem_app/python)
  set_tests_properties(yade_import_leaves_no_temp PROPERTIES TIMEOUT 120
    LABELS "integration;no_asan")
endif()
