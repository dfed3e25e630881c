#!/usr/bin/python3
"""scripts/mpmdem_tools/sweep.py: variants from a base scene with overrides, the CSV written row
by row (the rows before a failed run stay), its line ends, and the report written and printed.
The runs are stand-ins (the spec's own `run`): no program is started."""
import contextlib
import io
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from mpmdem_tools.sweep import StudySpec, Variant, derived, sweep  # noqa: E402


class Failed(Exception):
    pass


def fake_run(fail_at=None, watch=None):
    """A run that returns a summary from its scene (steps = 1000 x solver.cfl) and records
    its calls; the variant named fail_at raises Failed, as a failed mpm_app ends a study, after
    noting in calls what the file `watch` holds at that moment (what a killed study leaves)."""
    calls = []

    def run(app, scene, where, name, study):
        calls.append((app, where, name, study))
        if name == fail_at:
            calls.append(watch.read_bytes() if watch and watch.exists() else None)
            raise Failed(name)
        return {"steps": int(1000 * scene["solver"]["cfl"]), "run_s": 0.0}

    return run, calls


class Sweep(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.out = Path(self.dir.name)
        self.base = {"solver": {"cfl": 0.5, "flip": 0.99}, "grid": {"cell_size": 0.1}}
        self.variants = [Variant(f"cfl{c}", derived(self.base, {"solver.cfl": c}), {"cfl": c})
                         for c in (0.5, 0.25)]

    def tearDown(self):
        self.dir.cleanup()

    def metrics(self, v, s):
        return {"cfl": v.info["cfl"], "steps": s["steps"]}

    def test_derived_leaves_the_base_alone(self):
        doc = derived(self.base, {"solver.cfl": 0.25, "solver.flip": None})
        self.assertEqual(doc["solver"], {"cfl": 0.25})
        self.assertEqual(self.base["solver"], {"cfl": 0.5, "flip": 0.99})

    def test_rows_csv_and_report(self):
        run, calls = fake_run()
        spec = StudySpec("study", self.variants, self.metrics,
                         lambda rows: f"{len(rows)} rows\n", run=run, progress=False)
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            rows = sweep(spec, "APP", str(self.out))
        self.assertEqual(rows, [{"cfl": 0.5, "steps": 500}, {"cfl": 0.25, "steps": 250}])
        self.assertEqual([c[2] for c in calls], ["cfl0.5", "cfl0.25"])
        self.assertTrue(all(c[1] == str(self.out / "runs") for c in calls))
        self.assertEqual((self.out / "study.csv").read_bytes(),
                         b"cfl,steps\r\n0.5,500\r\n0.25,250\r\n")  # the csv module's line ends
        self.assertEqual((self.out / "table.md").read_text(), "2 rows\n")
        self.assertEqual(printed.getvalue(), "2 rows\n\n")

    def test_lineterminator_and_runs_in_out(self):
        run, calls = fake_run()
        spec = StudySpec("study", self.variants, self.metrics, run=run, runs_dir="",
                         csv_name="c.csv", csv_lineterminator="\n", progress=False)
        sweep(spec, "APP", str(self.out))
        self.assertEqual((self.out / "c.csv").read_bytes(), b"cfl,steps\n0.5,500\n0.25,250\n")
        self.assertTrue(all(c[1] == str(self.out) for c in calls))

    def test_rows_before_a_failed_run_stay(self):
        run, calls = fake_run(fail_at="cfl0.25", watch=self.out / "study.csv")
        spec = StudySpec("study", self.variants, self.metrics, lambda rows: "never\n", run=run,
                         progress=False)
        with self.assertRaises(Failed):
            sweep(spec, "APP", str(self.out))
        # On disk while the second run was still going (flushed), and after the study ended.
        self.assertEqual(calls[-1], b"cfl,steps\r\n0.5,500\r\n")
        self.assertEqual((self.out / "study.csv").read_bytes(), b"cfl,steps\r\n0.5,500\r\n")
        self.assertFalse((self.out / "table.md").exists())

    def test_no_row_no_csv(self):
        run, _ = fake_run()
        spec = StudySpec("study", self.variants, lambda v, s: None, run=run, progress=False)
        self.assertEqual(sweep(spec, "APP", str(self.out)), [])
        self.assertFalse((self.out / "study.csv").exists())


if __name__ == "__main__":
    unittest.main()
