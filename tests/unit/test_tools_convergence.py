#!/usr/bin/python3
"""scripts/mpmdem_tools/convergence.py against hand-computed cases."""
import math
import sys
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
from mpmdem_tools import convergence as cv  # noqa: E402


class Richardson(unittest.TestCase):
    def test_second_order_by_hand(self):
        # f(h) = 1 + h^2 on h = 0.4, 0.2, 0.1: f = 1.16, 1.04, 1.01.
        # p = ln(0.12 / 0.03) / ln 2 = 2; f_ext = 1.01 + (1.01 - 1.04) / 3 = 1.0;
        # GCI = 1.25 * 0.03 / 1.01 / 3 = 0.0123762...
        r = cv.richardson([1.16, 1.04, 1.01])
        self.assertEqual(r["kind"], "converging")
        self.assertAlmostEqual(r["p"], 2.0, places=12)
        self.assertAlmostEqual(r["extrapolated"], 1.0, places=12)
        self.assertAlmostEqual(r["gci"], 1.25 * 0.03 / 1.01 / 3, places=12)
        self.assertAlmostEqual(cv.observed_order([1.16, 1.04, 1.01]), 2.0, places=12)
        self.assertAlmostEqual(cv.extrapolate(1.04, 1.01, 2.0), 1.0, places=12)
        self.assertAlmostEqual(cv.gci(1.04, 1.01, 2.0), r["gci"], places=15)
        self.assertEqual(cv.richardson_text([1.16, 1.04, 1.01]), ("2.00", "1.000", "1.2 %"))

    def test_first_order_ratio_three(self):
        # f(h) = 2 + h on h = 0.9, 0.3, 0.1 (ratio 3): order 1, extrapolated 2.
        r = cv.richardson([2.9, 2.3, 2.1], ratio=3.0)
        self.assertAlmostEqual(r["p"], 1.0, places=12)
        self.assertAlmostEqual(r["extrapolated"], 2.0, places=12)

    def test_kinds(self):
        self.assertEqual(cv.richardson([1.0, 1.2, 1.1])["kind"], "oscillatory")
        self.assertEqual(cv.richardson([1.0, 1.1, 1.3])["kind"], "slow")
        self.assertEqual(cv.richardson([1.0, 1.1, 1.1])["kind"], "exact")
        self.assertEqual(cv.richardson_text([1.0, 1.2, 1.1]), ("oscillatory", "-", "-"))

    def test_order_from_errors(self):
        # e = h^2: 4e-2 -> 1e-2 halving h is order 2 (as scripts/verify_elastic reports it).
        self.assertAlmostEqual(cv.observed_order_from_errors(4e-2, 1e-2), 2.0, places=12)
        self.assertEqual(cv.observed_order_from_errors(0.3, 0.1),
                         math.log(0.3 / 0.1, 2))


if __name__ == "__main__":
    unittest.main()
