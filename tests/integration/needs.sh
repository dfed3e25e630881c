#!/usr/bin/env bash
# needs.sh DEP... -- COMMAND...: run COMMAND when every dependency DEP is here, else exit 77
# (CTest reports the test as skipped: SKIP_RETURN_CODE 77) and say which one is missing.
# Every test is registered on every machine (tests/CMakeLists.txt, mpmdem_test); CI makes a
# missing dependency a configure error instead (MPMDEM_REQUIRE_TEST_DEPS), so there it always runs.
#   yade          the YADE backend built into dem_app (dem_app --list-backends) and Debian's yade
#   yade-module   Debian's yade, imported as a Python module by /usr/bin/python3 (no backend)
#   clang-format  clang-format on PATH
#   mpi4py        Debian's python3-mpi4py (with numpy and yaml), imported by /usr/bin/python3
# Env: MPMDEM_BIN (build dir).
set -uo pipefail
skip() {
  echo "SKIPPED: $*"
  exit 77
}
deps=()
while (($#)) && [[ $1 != -- ]]; do deps+=("$1"); shift; done
[[ ${1:-} == -- ]] || { echo "needs.sh: usage: needs.sh DEP... -- COMMAND..." >&2; exit 2; }
shift
for d in "${deps[@]}"; do
  case $d in
    yade-module)
      [[ -x /usr/bin/yade ]] || skip "Debian's yade is not installed (/usr/bin/yade; apt-get install yade)" ;;
    yade)
      [[ -x /usr/bin/yade ]] || skip "Debian's yade is not installed (/usr/bin/yade; apt-get install yade)"
      dem_app=${MPMDEM_BIN:?MPMDEM_BIN not set}/dem_app/dem_app
      backends=$("$dem_app" --list-backends) || { echo "needs.sh: $dem_app --list-backends failed" >&2; exit 1; }
      grep -qx yade <<<"$backends" ||
        skip "dem_app was built without the YADE backend (configure with -DMPMDEM_WITH_YADE=ON; needs python3.11-dev and yade)" ;;
    clang-format)
      command -v clang-format >/dev/null || skip "clang-format is not installed (apt-get install clang-format)" ;;
    mpi4py)
      /usr/bin/python3 -c "import mpi4py, numpy, yaml" 2>/dev/null ||
        skip "Debian's python3-mpi4py is not installed for /usr/bin/python3 (apt-get install python3-mpi4py)" ;;
    *) echo "needs.sh: unknown dependency '$d'" >&2; exit 2 ;;
  esac
done
exec "$@"
