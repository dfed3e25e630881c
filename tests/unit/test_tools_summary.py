#!/usr/bin/python3
"""scripts/mpmdem_tools/summary.py: typed access, and errors that name the file and key."""
import json
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from mpmdem_tools.summary import SummaryError, read_summary  # noqa: E402


class ReadSummary(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.run = Path(self.dir.name)

    def tearDown(self):
        self.dir.cleanup()

    def write(self, doc):
        (self.run / "summary.json").write_text(json.dumps(doc))

    def test_keys_and_paths(self):
        self.write({"status": "complete", "steps": 12, "energy_budget": {"E_err_share": 0.01}})
        for where in (self.run, self.run / "summary.json", str(self.run)):
            s = read_summary(where)
            self.assertEqual(s["steps"], 12)
            self.assertEqual(s.path("energy_budget.E_err_share"), 0.01)
            self.assertTrue(s.complete)
            self.assertEqual(s.get("absent", 3), 3)
            self.assertIsInstance(s, dict)

    def test_missing_key_names_file_and_key(self):
        self.write({"status": "truncated", "error": "max steps"})
        s = read_summary(self.run)
        with self.assertRaises(SummaryError) as e:
            s["runout_m"]
        self.assertIn("runout_m", str(e.exception))
        self.assertIn(str(self.run / "summary.json"), str(e.exception))
        with self.assertRaises(SummaryError) as e:
            s.path("energy_budget.E_err_share")
        self.assertIn("energy_budget", str(e.exception))
        with self.assertRaises(SummaryError) as e:
            s.require_complete()
        self.assertIn("truncated", str(e.exception))

    def test_missing_or_broken_file(self):
        with self.assertRaises(SummaryError) as e:
            read_summary(self.run)
        self.assertIn("no summary.json", str(e.exception))
        (self.run / "summary.json").write_text("{not json")
        with self.assertRaises(SummaryError) as e:
            read_summary(self.run)
        self.assertIn("cannot read", str(e.exception))


if __name__ == "__main__":
    unittest.main()
