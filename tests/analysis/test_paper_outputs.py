import json
import pathlib
import tempfile
import unittest

from fixture_results import write_run  # first: puts analysis/ on the path

import paper_outputs

CACHE_STAGES = {"gbuffer": 0.01, "update": 0.02, "gather": 0.005}


class BuildFiguresAndTables(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.temp = tempfile.TemporaryDirectory()
        root = pathlib.Path(cls.temp.name) / "results"
        for s in range(2):
            for method, scale in (("mamba", 0.5), ("path_traced", 1.0)):
                curve = [(0.1 * k, scale * (1.0 + 0.1 * s) / k, scale * 0.5 / k) for k in range(1, 11)]
                write_run(root, "stores", f"{method}_{s}", method, s, curve, reference_noise={"total": 1e-3, "indirect": 2e-3},
                          probes=list(range(10, 20)) if method == "mamba" else None,
                          stages=CACHE_STAGES if method == "mamba" else None)
        write_run(root, "sponza_stores", "cards_0", "cards", 0, [(0.1, 1.0, 0.5), (0.3, 0.4, 0.2)], scene="sponza")
        cls.out = pathlib.Path(cls.temp.name) / "out"
        cls.outputs = paper_outputs.build_figures_and_tables(root, cls.out)

    @classmethod
    def tearDownClass(cls):
        cls.temp.cleanup()

    def test_outputs_json_is_what_was_returned(self):
        self.assertEqual(json.loads((self.out / "outputs.json").read_text()), self.outputs)
        self.assertEqual(self.outputs["runs_csv"], "runs.csv")
        self.assertTrue((self.out / "runs.csv").stat().st_size > 0)

    def test_every_figure_is_written_as_png_and_pdf(self):
        figures = self.outputs["figures"]
        kinds = {(f["kind"], f["scene"]) for f in figures}
        self.assertEqual(kinds, {("error_vs_time", "cornell_box"), ("stage_times", "cornell_box"), ("memory", "cornell_box"),
                                 ("probes", "cornell_box"), ("error_vs_time", "sponza"), ("stage_times", "sponza")})
        self.assertEqual(sum(f["kind"] == "error_vs_time" for f in figures), 4)  # total and indirect per scene
        for figure in figures:
            self.assertFalse(pathlib.PurePath(figure["path"]).is_absolute())
            self.assertTrue(figure["path"].startswith("figures/") and figure["path"].endswith(".png"))
            self.assertEqual(figure["pdf"], figure["path"][:-4] + ".pdf")
            self.assertTrue((self.out / figure["path"]).read_bytes().startswith(b"\x89PNG"), figure["path"])
            self.assertTrue((self.out / figure["pdf"]).read_bytes().startswith(b"%PDF"), figure["pdf"])
            self.assertTrue(figure["caption"] and "\n" not in figure["caption"])

    def test_every_table_is_written_as_markdown_and_latex(self):
        tables = self.outputs["tables"]
        self.assertEqual({t["kind"] for t in tables}, {"equal_time", "equal_error"})
        names = {t["markdown"] for t in tables}
        self.assertIn("tables/equal_time_stores_cornell_box_total.md", names)
        self.assertIn("tables/equal_error_stores_cornell_box_indirect.md", names)
        for table in tables:
            markdown, latex = (self.out / table["markdown"]).read_text(), (self.out / table["latex"]).read_text()
            self.assertIn("mean over seeds", markdown.splitlines()[0])
            self.assertIn("| method", markdown)
            self.assertIn(r"\toprule", latex)
            self.assertIn(r"\textbf{", latex)
            self.assertTrue("standard error" in table["caption"] or "SE" in table["caption"])


if __name__ == "__main__":
    unittest.main()
