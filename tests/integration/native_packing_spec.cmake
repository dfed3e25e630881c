# A native scene builds and exports its packings from coupling.native.packing_spec (issue 15);
# YADE builds the packings.
mpmdem_test(NAME native_packing_spec NEEDS yade COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/native_packing_spec.sh
            TIMEOUT 180 LABELS integration no_asan SERIAL)
