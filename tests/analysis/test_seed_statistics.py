import math
import unittest

import fixture_results  # noqa: F401  (analysis/ on the path)
import seed_statistics


class MeanAndStandardError(unittest.TestCase):
    def test_known_sample(self):
        # 1, 2, 3, 4: mean 2.5, sample variance 5/3, SE sqrt(5/3) / 2.
        mean, se, n = seed_statistics.mean_and_se([1.0, 2.0, 3.0, 4.0])
        self.assertEqual((mean, n), (2.5, 4))
        self.assertAlmostEqual(se, math.sqrt(5.0 / 3.0) / 2.0, places=12)

    def test_one_seed_has_no_spread(self):
        mean, se, n = seed_statistics.mean_and_se([0.3])
        self.assertEqual((mean, n), (0.3, 1))
        self.assertTrue(math.isnan(se))

    def test_a_missing_value_makes_the_mean_missing_unless_asked_otherwise(self):
        self.assertTrue(math.isnan(seed_statistics.mean_and_se([1.0, math.nan, 3.0])[0]))
        mean, se, n = seed_statistics.mean_and_se([1.0, math.nan, 3.0], require_all=False)
        self.assertEqual((mean, n), (2.0, 2))
        self.assertAlmostEqual(se, 1.0, places=12)  # sample sd sqrt(2), over sqrt(2)


class WithinSpreadOfBest(unittest.TestCase):
    def test_overlapping_intervals_are_marked_and_disjoint_ones_are_not(self):
        # Best 1.0 ± 0.1, i.e. [0.9, 1.1]; 1.15 ± 0.1 overlaps it, 1.25 ± 0.1 does not, and 1.2 ± 0.1
        # touches it exactly (|difference| = SE sum counts as within).
        marks = seed_statistics.within_spread_of_best([1.15, 1.0, 1.25, 1.2], [0.1, 0.1, 0.1, 0.1])
        self.assertEqual(list(marks), [True, False, False, True])

    def test_nothing_is_marked_without_a_spread(self):
        nan = math.nan
        self.assertEqual(list(seed_statistics.within_spread_of_best([1.0, 1.01], [nan, nan])), [False, False])
        self.assertEqual(list(seed_statistics.within_spread_of_best([1.0, 1.01], [nan, 0.5])), [False, False])

    def test_missing_entries_are_neither_best_nor_marked(self):
        marks = seed_statistics.within_spread_of_best([math.nan, 2.0, 2.1], [0.1, 0.1, 0.1])
        self.assertEqual(seed_statistics.best_index([math.nan, 2.0, 2.1]), 1)
        self.assertEqual(list(marks), [False, False, True])


if __name__ == "__main__":
    unittest.main()
