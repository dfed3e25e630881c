# Results bit for bit unchanged (tests/golden/golden.sh): each scene's physics hashed against
# tests/golden/hashes.txt, recorded before changes that must not change results.
foreach(_scene default elastic local)
  mpmdem_test(NAME golden_${_scene}_bitwise COMMAND bash ${PROJECT_SOURCE_DIR}/tests/golden/golden.sh ${_scene}
              TIMEOUT 240 LABELS integration no_asan SERIAL)
endforeach()
mpmdem_test(NAME golden_yade_bitwise NEEDS yade COMMAND bash ${PROJECT_SOURCE_DIR}/tests/golden/golden.sh yade
            TIMEOUT 240 LABELS integration no_asan SERIAL)
