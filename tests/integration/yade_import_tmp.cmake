# Importing YADE leaves no folder in $TMPDIR or /tmp (yade_import_tmp.py says which and why).
# (Newlines, not ';', separate the shell's commands: mpmdem_test's arguments are a CMake list.)
mpmdem_test(NAME yade_import_leaves_no_temp NEEDS yade-module
  COMMAND sh -c "t=$(mktemp -d) && TMPDIR=$t /usr/bin/python3 \"$1\" \"$2\"\nrc=$?\nrm -rf $t\nexit $rc"
          sh ${CMAKE_CURRENT_LIST_DIR}/yade_import_tmp.py ${PROJECT_SOURCE_DIR}/dem_app/python
  TIMEOUT 120 LABELS integration no_asan)
