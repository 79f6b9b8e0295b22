import math
import unittest

import fixture_results  # noqa: F401  (analysis/ on the path)
import error_curves

# error = 1 / t^2 at t = 1, 2, 4: a straight line of slope -2 on log-log axes.
TIMES, ERRORS = [1.0, 2.0, 4.0], [1.0, 0.25, 0.0625]


class TimeToReach(unittest.TestCase):
    def test_interpolates_on_the_log_log_curve(self):
        # Between (1, 1) and (2, 0.25): log t = log 2 * log(0.5) / log(0.25) = log 2 / 2, t = sqrt(2)
        # (a straight line in linear axes would give 1 + 0.5 / 0.75 = 1.667).
        self.assertAlmostEqual(error_curves.time_to_reach(TIMES, ERRORS, 0.5), math.sqrt(2.0), places=12)
        # Between (2, 0.25) and (4, 0.0625): 0.1 = t^-2, t = sqrt(10).
        self.assertAlmostEqual(error_curves.time_to_reach(TIMES, ERRORS, 0.1), math.sqrt(10.0), places=12)

    def test_first_crossing_of_a_curve_that_goes_back_up(self):
        # Reaches 0.5 between 1 s and 2 s, goes up again at 3 s and down at 4 s: the first crossing counts.
        self.assertAlmostEqual(error_curves.time_to_reach([1, 2, 3, 4], [1.0, 0.25, 2.0, 0.1], 0.5), math.sqrt(2.0),
                               places=12)

    def test_a_target_met_at_the_first_frame_or_never(self):
        self.assertEqual(error_curves.time_to_reach(TIMES, ERRORS, 2.0), 1.0)
        self.assertEqual(error_curves.time_to_reach(TIMES, ERRORS, 0.0625), 4.0)
        self.assertTrue(math.isnan(error_curves.time_to_reach(TIMES, ERRORS, 0.06)))

    def test_unmeasured_frames_are_skipped(self):
        self.assertAlmostEqual(error_curves.time_to_reach([1.0, 1.5, 2.0], [1.0, math.nan, 0.25], 0.5), math.sqrt(2.0),
                               places=12)


class ErrorAt(unittest.TestCase):
    def test_log_log_interpolation_inside_and_nothing_outside(self):
        values = error_curves.error_at(TIMES, ERRORS, [0.5, 1.0, math.sqrt(2.0), 3.0, 4.0, 5.0])
        self.assertTrue(math.isnan(values[0]) and math.isnan(values[5]))
        for got, want in zip(values[1:5], [1.0, 0.5, 1.0 / 9.0, 0.0625]):
            self.assertAlmostEqual(got, want, places=12)

    def test_common_times_span_where_every_curve_is_measured(self):
        times = error_curves.common_times([([1.0, 4.0], [1.0, 0.1]), ([2.0, 8.0], [1.0, 0.1])], points=3)
        self.assertEqual(len(times), 3)
        self.assertAlmostEqual(times[0], 2.0)
        self.assertAlmostEqual(times[1], math.sqrt(8.0))
        self.assertAlmostEqual(times[2], 4.0)
        self.assertEqual(len(error_curves.common_times([([1.0, 2.0], [1.0, 0.5]), ([3.0, 4.0], [1.0, 0.5])])), 0)


class ErrorTargets(unittest.TestCase):
    def test_one_two_five_values_from_the_lowest_final_to_the_highest_first_error(self):
        self.assertEqual(error_curves.error_targets([1.0, 0.4], [0.03, 0.2]), [0.05, 0.1, 0.2, 0.5])

    def test_at_most_the_number_asked_with_both_ends_kept(self):
        targets = error_curves.error_targets([10.0], [1e-4], most=4)
        self.assertEqual(len(targets), 4)
        self.assertAlmostEqual(targets[0], 1e-4)
        self.assertAlmostEqual(targets[-1], 5.0)


if __name__ == "__main__":
    unittest.main()
