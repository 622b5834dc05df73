#!/usr/bin/env python3
"""The comparison rules of run_case.py: each accepts what its text says and refuses the rest."""

import math
import unittest

import run_case


def problems(out, ref, rules):
    return run_case.compare({"v": out}, {"v": ref}, rules)


class Rules(unittest.TestCase):
    def test_no_rule_means_bit_for_bit(self):
        self.assertEqual(problems(0.1, 0.1, []), [])
        self.assertEqual(len(problems(math.nextafter(0.1, 1.0), 0.1, [])), 1)

    def test_abs_and_rel_take_the_larger(self):
        rules = [{"path": "v", "abs": 0.01, "rel": 0.1}]
        self.assertEqual(problems(1.09, 1.0, rules), [])
        self.assertEqual(len(problems(1.11, 1.0, rules)), 1)
        self.assertEqual(problems(0.009, 0.0, rules), [])
        self.assertEqual(len(problems(0.011, 0.0, rules)), 1)

    def test_factor_bounds_both_ways(self):
        rules = [{"path": "v", "factor": 3}]
        for out in (2e-4, 5.9e-4, 0.7e-4):
            self.assertEqual(problems(out, 2e-4, rules), [], out)
        for out in (6.1e-4, 0.66e-4, 0.0, -2e-4, math.nan, math.inf):
            self.assertEqual(len(problems(out, 2e-4, rules)), 1, out)

    def test_factor_refuses_a_reference_that_is_not_positive(self):
        # a factor of zero is every factor of zero, so only equal values pass (as with no rule)
        self.assertEqual(problems(0.0, 0.0, [{"path": "v", "factor": 3}]), [])
        self.assertEqual(len(problems(1e-4, 0.0, [{"path": "v", "factor": 3}])), 1)

    def test_first_matching_rule_decides(self):
        loose, exact = {"path": "v", "rel": 0.5}, {"path": "v", "abs": 0}
        self.assertEqual(problems(1.4, 1.0, [loose, exact]), [])
        self.assertEqual(len(problems(1.4, 1.0, [exact, loose])), 1)

    def test_ignore_drops_the_value_from_both_sides(self):
        rules = [{"path": "v", "ignore": True}]
        self.assertEqual(run_case.strip_ignored({"v": 1, "w": 2}, rules), {"w": 2})

if __name__ == "__main__":
    unittest.main()
