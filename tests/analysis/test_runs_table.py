import math
import pathlib
import subprocess
import sys
import tempfile
import unittest

import pandas as pd

import fixture_results  # first: puts analysis/ on the path
import configurations
import runs_table
from fixture_results import write_run
from input_error import InputError

CURVE = [(0.1, 0.8, 0.4), (0.2, 0.4, None), (0.4, 0.2, 0.1)]  # the second frame's indirect not measured


class RunsTable(unittest.TestCase):
    def setUp(self):
        self.temp = tempfile.TemporaryDirectory()
        self.root = pathlib.Path(self.temp.name)

    def tearDown(self):
        self.temp.cleanup()

    def write_sweep(self):
        for cell in (0.1, 0.2):
            write_run(self.root, "stores", f"mamba_cell-{cell:g}", "mamba", 0, CURVE, method_params={"cell_size": cell},
                      sweep_axes={"method.cell_size": cell, "seed": 0}, run_id=f"{int(cell * 10):016x}",
                      probes=[10, 20, 30], reference_noise={"total": 0.001, "indirect": 0.002})
        write_run(self.root, "stores", "path_traced", "path_traced", 3, CURVE, method_params={"spp": 4})

    def test_one_row_per_run_and_checkpoint_with_stable_columns(self):
        self.write_sweep()
        table = runs_table.load_runs(self.root)
        # 2 frame checkpoints, 2 seconds checkpoints, the final state; 3 runs.
        self.assertEqual(len(table), 3 * 5)
        self.assertEqual(list(table.columns[:6]), ["run_id", "experiment", "run", "method", "scene", "seed"])
        for column in ("method_cell_size", "spp", "resolution", "frames", "checkpoint_kind", "checkpoint_value", "frame",
                       "seconds", "relmse_total", "relmse_indirect", "mse_total", "probes", "bytes",
                       "reference_noise_total", "frames_rendered", "stopped_by"):
            self.assertIn(column, table.columns)
        self.assertNotIn("method_name", table.columns)  # it is "method"
        self.assertIn("relmse_direct", table.columns)  # never measured here, but always a column
        self.assertTrue(table["relmse_direct"].isna().all())
        self.assertNotIn("seed_", "".join(table.columns))
        row = table[(table["run"] == "mamba_cell-0.2") & (table["checkpoint_kind"] == "seconds")
                    & (table["checkpoint_value"] == 0.25)].iloc[0]
        # The last frame finished by 0.25 s is frame 1 (0.2 s): indirect unmeasured there.
        self.assertEqual((row["frame"], row["seconds"], row["relmse_total"]), (1, 0.2, 0.4))
        self.assertTrue(math.isnan(row["relmse_indirect"]))
        self.assertEqual((row["probes"], row["bytes"]), (20, 2000))
        self.assertEqual((row["method_cell_size"], row["scene"], row["resolution"], row["run_id"]),
                         (0.2, "cornell_box", "32x24", "0000000000000002"))
        traced = table[table["method"] == "path_traced"]
        self.assertEqual(set(traced["spp"]), {4.0})
        self.assertTrue(traced["probes"].isna().all() and traced["run_id"].isna().all())
        final = traced[traced["checkpoint_kind"] == "final"].iloc[0]
        self.assertEqual((final["frame"], final["seconds"], final["relmse_total"]), (2, 0.4, 0.2))

    def test_runs_csv_reads_back_with_numbers_as_numbers_and_no_nan_or_inf_text(self):
        self.write_sweep()
        # A run that stopped before the 1 s checkpoint: frame null there.
        write_run(self.root, "stores", "short", "cards", 0, [(0.05, 1.0, 0.5)])
        file = self.root / "runs.csv"
        runs_table.write_csv(runs_table.load_runs(self.root), file)
        text = file.read_text()
        for word in ("nan", "inf", "NaN", "<NA>", "None"):
            self.assertNotIn(word, text)
        back = runs_table.read_csv(file)
        self.assertEqual(list(back.columns), list(runs_table.load_runs(self.root).columns))
        self.assertEqual(set(back["run_id"].dropna()), {"0000000000000001", "0000000000000002"})
        for column in ("seed", "frames", "frame", "checkpoint_value", "seconds", "relmse_total", "relmse_indirect", "probes",
                       "bytes", "method_cell_size", "spp", "reference_noise_total"):
            self.assertTrue(pd.api.types.is_numeric_dtype(back[column]), f"{column}: {back[column].dtype}")
        self.assertTrue(pd.api.types.is_integer_dtype(back["seed"]) and pd.api.types.is_integer_dtype(back["frame"]))
        # Plain pandas reads the same numbers.
        plain = pd.read_csv(file)
        self.assertTrue(all(pd.api.types.is_numeric_dtype(plain[c]) for c in ("seed", "frame", "relmse_total", "bytes")))
        stopped = back[(back["run"] == "short") & (back["checkpoint_kind"] == "seconds")]
        self.assertEqual(len(stopped), 2)
        self.assertTrue(stopped["frame"].isna().all() and stopped["relmse_total"].isna().all())
        self.assertEqual(set(back.loc[back["method"] == "path_traced", "spp"]), {4})

    def test_swept_parameters_are_found_without_sweep_axes(self):
        # Older manifests have no "sweep": a key that differs between runs of one method is swept.
        write_run(self.root, "e", "a", "mamba", 0, CURVE, method_params={"history": 16})
        write_run(self.root, "e", "b", "mamba", 0, CURVE, method_params={"history": 32})
        write_run(self.root, "e", "c", "cards", 0, CURVE, method_params={"card_resolution": 8})
        table = runs_table.load_runs(self.root / "e")  # an experiment folder
        self.assertIn("method_history", table.columns)
        self.assertNotIn("method_card_resolution", table.columns)  # one value per method: not swept
        self.assertEqual(sorted(table["method_history"].dropna().unique()), [16, 32])

    def test_hidden_folders_are_not_runs(self):
        write_run(self.root, "e", "run", "mamba", 0, CURVE)
        write_run(self.root, "e", ".staging-run-1-0", "mamba", 1, CURVE)
        write_run(self.root, ".old-e", "run", "mamba", 2, CURVE)
        self.assertEqual(set(runs_table.load_runs(self.root)["seed"]), {0})


class Configurations(unittest.TestCase):
    def test_runs_differing_only_in_seed_are_one_configuration_labelled_by_what_differs(self):
        with tempfile.TemporaryDirectory() as temp:
            for cell in (0.1, 0.2):
                for seed in (0, 1):
                    write_run(temp, "e", f"m_{cell:g}_{seed}", "mamba", seed, CURVE, method_params={"cell_size": cell})
            write_run(temp, "e", "pt", "path_traced", 0, CURVE, method_params={"spp": 4})
            groups = configurations.groups(runs_table.load_runs(temp))
        self.assertEqual([sorted(rows["run"].unique()) for _, rows in groups],
                         [["pt"], ["m_0.1_0", "m_0.1_1"], ["m_0.2_0", "m_0.2_1"]])  # path_traced first
        # spp differs between methods only: not part of a label.
        self.assertEqual(configurations.labels([conf for conf, _ in groups]),
                         ["path_traced", "mamba (method_cell_size=0.1)", "mamba (method_cell_size=0.2)"])


class BadInput(unittest.TestCase):
    def setUp(self):
        self.temp = tempfile.TemporaryDirectory()
        self.root = pathlib.Path(self.temp.name)

    def tearDown(self):
        self.temp.cleanup()

    def test_a_folder_without_runs(self):
        with self.assertRaisesRegex(InputError, f"^{self.root}: no runs"):
            runs_table.load_runs(self.root)

    def test_an_unreadable_json_file_is_named(self):
        folder = write_run(self.root, "e", "run", "mamba", 0, CURVE)
        (folder / "metrics.json").write_text("{ not json")
        with self.assertRaisesRegex(InputError, f"^{folder / 'metrics.json'}: not readable as JSON"):
            runs_table.load_runs(self.root)

    def test_a_bad_frame_line_is_named_with_its_line_number(self):
        folder = write_run(self.root, "e", "run", "mamba", 0, CURVE)
        with open(folder / "frames.jsonl", "a") as out:
            out.write("[1, 2]\n")
        with self.assertRaisesRegex(InputError, f"^{folder / 'frames.jsonl'}:4: expected a frame record with a \"frame\" index"):
            runs_table.load_runs(self.root)

    def test_malformed_checkpoints_are_named(self):
        folder = write_run(self.root, "e", "run", "mamba", 0, CURVE)
        (folder / "metrics.json").write_text('{"checkpoints": {"frames": [1, 2]}}')
        with self.assertRaisesRegex(InputError, f"^{folder / 'metrics.json'}: \"checkpoints\".\"frames\": expected a list"):
            runs_table.load_runs(self.root)

    def test_the_command_prints_the_error_and_exits_2(self):
        folder = write_run(self.root, "e", "run", "mamba", 0, CURVE)
        (folder / "manifest.json").write_text("[]")
        out = self.root / "out"
        done = subprocess.run([sys.executable, str(fixture_results.ANALYSIS / "paper_outputs.py"), str(self.root), "--out",
                               str(out)], capture_output=True, text=True)
        self.assertEqual(done.returncode, 2)
        self.assertEqual(done.stderr, f"error: {folder / 'manifest.json'}: expected a JSON object, got list\n")
        self.assertFalse(out.exists())


if __name__ == "__main__":
    unittest.main()
