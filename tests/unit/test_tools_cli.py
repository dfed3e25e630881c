#!/usr/bin/python3
"""scripts/mpmdem (mpmdem_tools.__main__): the subcommands name existing scripts; bad
subcommands exit 2 with a message; nothing is built or run."""
import subprocess
import sys
import unittest
from pathlib import Path

SCRIPTS = Path(__file__).resolve().parents[2] / "scripts"
sys.path.insert(0, str(SCRIPTS))
from mpmdem_tools import __main__ as cli  # noqa: E402


def mpmdem(*args):
    return subprocess.run([str(SCRIPTS / "mpmdem"), *args], capture_output=True, text=True)


class Cli(unittest.TestCase):
    def test_every_subcommand_names_an_executable_script(self):
        for table in (cli.SCRIPTS, cli.BENCHES, cli.STUDIES):
            for name, script in table.items():
                path = SCRIPTS / script
                self.assertTrue(path.is_file(), f"{name}: {path} missing")
                self.assertTrue(path.stat().st_mode & 0o111, f"{name}: {path} not executable")

    def test_study_list_and_errors(self):
        r = mpmdem("study", "--list")
        self.assertEqual(r.returncode, 0)
        self.assertIn("grid_convergence", r.stdout)
        self.assertIn("scripts/grid_convergence_study", r.stdout)
        for args, text in ((("study", "nope"), "study needs a NAME"),
                           (("bench", "gpu"), "bench needs mpm or dem"),
                           (("frobnicate",), "unknown subcommand 'frobnicate'"), ((), "Usage")):
            r = mpmdem(*args)
            self.assertEqual(r.returncode, 2, args)
            self.assertIn(text, r.stderr, args)

    def test_delegates_with_the_scripts_own_exit_code(self):
        # scripts/runout_vs_dissipation without a folder: its own message and exit 2.
        r = mpmdem("study", "runout_vs_dissipation")
        self.assertEqual(r.returncode, 2)
        self.assertIn("give one or more folders of column runs", r.stderr)
        r = mpmdem("bench", "mpm", "--help")
        self.assertEqual(r.returncode, 0)
        self.assertIn("MPM cost per material-point-step", r.stdout)


if __name__ == "__main__":
    unittest.main()
