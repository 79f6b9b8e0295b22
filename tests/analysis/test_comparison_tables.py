import math
import pathlib
import tempfile
import unittest

from fixture_results import write_run  # first: puts analysis/ on the path

import comparison_tables
import results_reader
import runs_table


def se(values):
    """Standard error of the mean, written out: sqrt(sum (x - mean)^2 / (n - 1)) / sqrt(n)."""
    mean = sum(values) / len(values)
    return math.sqrt(sum((x - mean) ** 2 for x in values) / (len(values) - 1)) / math.sqrt(len(values))


class ComparisonTables(unittest.TestCase):
    """mamba and path_traced with 3 seeds each, cards with one that stops at 0.5 s."""

    @classmethod
    def setUpClass(cls):
        cls.temp = tempfile.TemporaryDirectory()
        root = pathlib.Path(cls.temp.name)
        for s in range(3):
            write_run(root, "e", f"mamba_{s}", "mamba", s, [(0.1, 1.0, None), (0.2, 0.1 * (s + 1), None), (1.0, 0.05 * (s + 1), None)])
            write_run(root, "e", f"pt_{s}", "path_traced", s, [(0.1, 2.0, None), (0.2, 0.5 + 0.1 * s, None), (1.0, 0.08 + 0.01 * s, None)])
        write_run(root, "e", "cards_0", "cards", 0, [(0.1, 3.0, None), (0.2, 0.9, None), (0.5, 0.3, None)])
        runs = results_reader.read_runs(root)
        cls.runs, cls.frames = runs_table.runs_table(runs), runs_table.frames_table(runs)

    @classmethod
    def tearDownClass(cls):
        cls.temp.cleanup()

    def test_equal_time_is_the_mean_over_seeds_with_its_standard_error(self):
        table = comparison_tables.equal_time(self.runs, "total")
        self.assertEqual(table.row_labels, ["path_traced", "mamba", "cards"])
        self.assertEqual(table.column_labels, ["0.25 s", "1 s"])
        self.assertEqual(table.seeds, [3, 3, 1])
        self.assertAlmostEqual(table.means[1, 0], 0.2, places=12)
        self.assertAlmostEqual(table.ses[1, 0], se([0.1, 0.2, 0.3]), places=12)
        self.assertAlmostEqual(table.means[0, 1], 0.09, places=12)
        self.assertAlmostEqual(table.ses[0, 1], se([0.08, 0.09, 0.10]), places=12)
        self.assertAlmostEqual(table.means[2, 0], 0.9)
        self.assertTrue(math.isnan(table.ses[2, 0]))  # one seed: no spread
        self.assertTrue(math.isnan(table.means[2, 1]))  # stopped before 1 s

    def test_equal_error_interpolates_each_seed_on_its_log_log_curve(self):
        table = comparison_tables.equal_error(self.frames, "total", targets=[0.01, 0.5])
        self.assertEqual(table.column_labels, ["0.5", "0.01"])  # the highest error first
        # mamba seed s falls from 1 at 0.1 s to e = 0.1 (s + 1) at 0.2 s: reaches 0.5 at
        # 0.1 * 2^(ln 0.5 / ln e).
        times = [0.1 * 2.0 ** (math.log(0.5) / math.log(0.1 * (s + 1))) for s in range(3)]
        self.assertAlmostEqual(table.means[1, 0], sum(times) / 3, places=12)
        self.assertAlmostEqual(table.ses[1, 0], se(times), places=12)
        # path_traced reaches 0.5 exactly at 0.2 s in seed 0, between 0.2 s and 1 s in the others.
        pt = [0.2] + [0.2 * 5.0 ** (math.log(0.5 / e) / math.log(f / e)) for e, f in ((0.6, 0.09), (0.7, 0.10))]
        self.assertAlmostEqual(table.means[0, 0], sum(pt) / 3, places=12)
        self.assertTrue(all(math.isnan(v) for v in table.means[:, 1]))  # no run reaches 0.01
        self.assertEqual(comparison_tables.without_empty_columns(table).column_labels, ["0.5"])

    def test_latex_bolds_the_best_per_column_and_daggers_entries_within_its_spread(self):
        text = comparison_tables.latex(comparison_tables.equal_time(self.runs, "total"))
        for rule in (r"\toprule", r"\midrule", r"\bottomrule"):
            self.assertEqual(text.count(rule), 1)
        rows = {line.split(" & ")[0]: line.split(" & ")[2:] for line in text.splitlines() if line.endswith(r"\\")}
        # At 0.25 s mamba (0.2 ± 0.058) is best, path_traced (0.6 ± 0.058) and cards (0.9, no spread) are
        # outside its spread. At 1 s path_traced (0.09 ± 0.0058) is best and mamba (0.1 ± 0.029) within it.
        self.assertEqual(rows["mamba"][0], r"\textbf{0.2 $\pm$ 0.058}")
        self.assertEqual(rows["path\\_traced"][0], r"0.6 $\pm$ 0.058")
        self.assertEqual(rows["cards"][0], "0.9")
        self.assertEqual(rows["path\\_traced"][1], r"\textbf{0.09 $\pm$ 0.0058} \\")
        self.assertEqual(rows["mamba"][1], r"0.1 $\pm$ 0.029$^{\dagger}$ \\")
        self.assertEqual(rows["cards"][1], r"--- \\")
        self.assertIn("standard error of the mean", text)

    def test_markdown_marks_the_same_entries(self):
        text = comparison_tables.markdown(comparison_tables.equal_time(self.runs, "total"))
        self.assertIn("| mamba | 3 | **0.2 ± 0.058** | 0.1 ± 0.029† |", text)
        self.assertIn("| cards | 1 | 0.9 | — |", text)
        self.assertIn("† within the spread of the best", text)


if __name__ == "__main__":
    unittest.main()
