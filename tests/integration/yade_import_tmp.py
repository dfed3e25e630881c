"""Importing YADE (dem_app/python/mpmdem_packing.py, _import_yade) leaves no folder behind.

Every YADE process used to leave one with a symlink in $TMPDIR (194 after a day of tests) and
YADE's own /tmp/yade-XXXXXX (a fixed /tmp, not $TMPDIR; 542 after two days of tests). Run with
TMPDIR set to a fresh, empty folder (yade_import_tmp.cmake): after the import that folder must
be empty, the process's /tmp/yade-* must be gone, and YADE's O must still answer.
Usage: yade_import_tmp.py PYTHON_DIR
"""
import os
import sys

sys.path.insert(0, sys.argv[1])
import mpmdem_packing as pk  # noqa: E402

y = pk._import_yade()
left = os.listdir(os.environ["TMPDIR"])
assert not left, f"left in $TMPDIR: {left}"
own = os.path.dirname(y.O.tmpFilename())
assert own.startswith("/tmp/yade-"), own
assert not os.path.exists(own), f"YADE's {own} is left"
y.O.reset()
assert y.O.iter == 0
print(f"no temp folder left ({own} removed); O answers")
