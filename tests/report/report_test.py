#!/usr/bin/python3
"""The report (analysis/report.py, `gibench report`): image grids, probe views and the HTML page, the
page checked in headless Chromium.

usage: GIBENCH_BINARY=build/gibench /usr/bin/python3 tests/report/report_test.py
ctest runs it as Report.HtmlInChromium. Exit code 77 (ctest's skip) when every other test passed but
Chromium cannot run here; without GIBENCH_BINARY the tests that need real runs are skipped.
"""

import html
import io
import json
import math
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import types
import unittest
import unittest.mock

import numpy as np

SOURCE = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(SOURCE / "analysis"))

import exr_io  # noqa: E402
import html_report  # noqa: E402
import image_grid  # noqa: E402
import probe_views  # noqa: E402
import report  # noqa: E402
import results_reader  # noqa: E402
from input_error import InputError  # noqa: E402

PYTHON = "/usr/bin/python3"
SKIP_CODE = 77
CHROMIUM = shutil.which("chromium")
chromium_unavailable = []  # why Chromium could not run, when it could not

# Injected into a copy of the page: after load, which images loaded, and what the first A/B view does
# when its slider moves and when it is zoomed by the wheel.
CHECK_SCRIPT = """
window.addEventListener('load', function () {
  var result = { images: [], compare: null };
  Array.prototype.forEach.call(document.images, function (img) {
    result.images.push({ src: img.getAttribute('src'), loaded: img.complete && img.naturalWidth > 0 });
  });
  var root = document.querySelector('.compare');
  if (root) {
    var slider = root.querySelector('input.ab-slider'), viewport = root.querySelector('.viewport');
    var a = root.querySelector('.layer.a img'), b = root.querySelector('.layer.b img');
    var before = root.querySelector('.layer.b').style.clipPath;
    slider.value = 250;
    slider.dispatchEvent(new Event('input'));
    var after = root.querySelector('.layer.b').style.clipPath;
    var r = viewport.getBoundingClientRect();
    viewport.dispatchEvent(new WheelEvent('wheel', { deltaY: -300, clientX: r.left + r.width / 3, clientY: r.top + r.height / 3,
                                                     bubbles: true, cancelable: true }));
    result.compare = { clipBefore: before, clipAfter: after, transformA: a.style.transform, transformB: b.style.transform };
  }
  var pre = document.createElement('pre');
  pre.id = 'load-check';
  pre.textContent = JSON.stringify(result);
  document.body.appendChild(pre);
});
"""


def gibench(*args, check=True):
    binary = os.environ["GIBENCH_BINARY"]
    done = subprocess.run([binary, *args], cwd=SOURCE, capture_output=True, text=True, timeout=120)
    if check and done.returncode != 0:
        raise AssertionError(f"gibench {' '.join(args)} exited {done.returncode}: {done.stderr}")
    return done


def make_fixture(root: pathlib.Path):
    """Three tiny Cornell-box runs against one reference: mamba with its probe views, dense_grid, and
    path tracing at 4 spp; 32x32 pixels, 8 frames."""
    common = ["--results", str(root), "--set", "camera.resolution=[32,32]", "--set", "frames=8", "--set", "reference.spp=256",
              "--set", "experiment=fixture"]
    gibench("reference", "configs/cornell_box.json", *common)
    methods = {
        "mamba": {"name": "mamba", "fine_cell_size_relative": 0.08, "allocation_tile": 8, "probe_views": True},
        "dense_grid": {"name": "dense_grid", "cell_size_relative": 0.08, "allocation_tile": 8},
        "path_traced": {"name": "path_traced", "spp": 4},
    }
    for name, method in methods.items():
        gibench("run", "configs/cornell_box.json", *common, "--set", f"method={json.dumps(method)}", "--set", f"run={name}")


def chromium(*args, profile: pathlib.Path) -> subprocess.CompletedProcess:
    return subprocess.run([CHROMIUM, "--headless=new", "--no-sandbox", "--disable-gpu", f"--user-data-dir={profile}",
                           "--virtual-time-budget=5000", *args], capture_output=True, text=True, timeout=90)


class ImageGridTest(unittest.TestCase):
    def test_error_map_is_the_per_pixel_relmse_term_averaged_over_channels(self):
        image = np.array([[[1.0, 2.0, 3.0], [0.0, 0.0, 0.0]]])
        reference = np.array([[[1.0, 1.0, 1.0], [0.1, 0.0, 0.0]]])
        error = image_grid.relative_squared_error(image, reference)
        # pixel 0: (0 + 1/1.01 + 4/1.01) / 3; pixel 1: (0.01 / (0.01 + 0.01) + 0 + 0) / 3
        np.testing.assert_allclose(error, [[5.0 / 1.01 / 3.0, 0.5 / 3.0]], rtol=1e-12)

    def test_every_image_of_a_grid_has_the_references_exposure(self):
        rng = np.random.default_rng(3)
        reference = rng.uniform(0.0, 2.0, (12, 16, 3))
        half = 0.5 * reference
        with tempfile.TemporaryDirectory() as out:
            grid = image_grid.compose_grid("s", "s", reference, [image_grid.Column("same", "mamba", reference.copy()),
                                                                 image_grid.Column("half", "dense_grid", half)], out)
            exposure = image_grid.exposure_for(reference)
            self.assertEqual(grid.exposure, exposure)
            np.testing.assert_array_equal(grid.displays["same"], grid.displays["reference"])
            np.testing.assert_array_equal(grid.displays["half"], image_grid.tone_map(half, exposure))
            # Exposed on its own, the half-bright image would look like the reference: the grid must not.
            np.testing.assert_allclose(image_grid.tone_map(half, image_grid.exposure_for(half)), grid.displays["reference"], atol=2e-3)
            self.assertGreater(np.abs(grid.displays["half"] - grid.displays["reference"]).max(), 0.05)
            # The A/B images are the same displays in 8 bits.
            for entry in grid.comparison:
                png = exr_io.read_layer(pathlib.Path(out) / entry["path"], "total")[:, :, :3]
                np.testing.assert_allclose(png, grid.displays[entry["label"]], atol=0.5 / 255 + 1e-6)
            for key in ("path", "pdf"):
                self.assertGreater((pathlib.Path(out) / grid.figure[key]).stat().st_size, 0)

    def test_the_automatic_crop_is_where_the_best_cache_errs_most(self):
        reference = np.full((40, 40, 3), 0.5)
        good, bad = reference.copy(), reference.copy()
        good[30:36, 4:10] = 3.0  # the better cache's worst place
        bad[:, :] = 0.9
        with tempfile.TemporaryDirectory() as out:
            grid = image_grid.compose_grid("s", "s", reference, [image_grid.Column("bad", "mamba", bad),
                                                                 image_grid.Column("good", "dense_grid", good)], out)
        size = image_grid.default_region_size(40, 40)
        self.assertEqual(size, 10)
        ((x, y, w, h),) = grid.regions
        self.assertEqual((w, h), (10, 10))
        self.assertTrue(x <= 4 and x + w >= 10 and y <= 30 and y + h >= 36, grid.regions)

    def test_equal_time_takes_final_images_at_one_budget_else_the_saved_frames_nearest_the_fastest_runs_end(self):
        with tempfile.TemporaryDirectory() as folder:
            def run(name, seconds, saved=(), budget=None):
                path = pathlib.Path(folder) / name
                path.mkdir()
                for frame in saved:
                    (path / f"frame_{frame:04d}.exr").touch()
                frames = [{"frame": f, "cumulative_seconds": s} for f, s in enumerate(seconds)]
                return results_reader.Run(path, {"config": {"budget": budget}}, {}, frames)

            fast = run("fast", [0.1, 0.2, 0.3])
            slow = run("slow", [0.25, 0.5, 0.75, 1.0], saved=(0, 1, 2))
            picks, note = image_grid.equal_time_images([fast, slow])
            self.assertEqual([(p[1].name, p[2]) for p in picks], [("image.exr", 0.3), ("frame_0000.exr", 0.25)])
            self.assertIn("closest to 0.3 s", note)

            unsaved = run("unsaved", [0.5, 1.0])
            picks, note = image_grid.equal_time_images([fast, unsaved])
            self.assertEqual([(p[1].name, p[2]) for p in picks], [("image.exr", 0.3), ("image.exr", 1.0)])
            self.assertIn("times differ", note)

            budgeted = [run("a", [0.4, 1.1], saved=(0,), budget={"seconds": 1.0}), run("b", [0.9, 1.05], budget={"seconds": 1.0})]
            picks, note = image_grid.equal_time_images(budgeted)
            self.assertEqual([p[1].name for p in picks], ["image.exr", "image.exr"])
            self.assertIn("budget of 1 s", note)

    def test_a_region_outside_the_image_is_an_input_error(self):
        reference = np.ones((8, 8, 3))
        with tempfile.TemporaryDirectory() as out, self.assertRaises(InputError) as caught:
            image_grid.compose_grid("box", "box", reference, [image_grid.Column("m", "mamba", reference)], out, regions=[(4, 4, 8, 8)])
        self.assertIn("scene box: region 4,4,8,8 is not inside the 8x8 image", str(caught.exception))


class ProbeViewsTest(unittest.TestCase):
    def test_uncovered_pixels_are_marked_exactly_where_a_surface_has_no_coverage(self):
        rng = np.random.default_rng(5)
        coverage = (rng.uniform(size=(9, 11, 1)) < 0.5).astype(np.float32)
        depth = np.where(rng.uniform(size=(9, 11, 1)) < 0.8, rng.uniform(0.5, 2.0, (9, 11, 1)), 0.0)
        display = rng.uniform(0.2, 0.8, (9, 11, 3))
        mask = probe_views.uncovered_mask(coverage, depth)
        np.testing.assert_array_equal(mask, (coverage[:, :, 0] == 0) & (depth[:, :, 0] > 0))
        self.assertTrue(mask.any() and not mask.all())
        marked = probe_views.mark_uncovered(display, mask)
        np.testing.assert_array_equal(marked[mask], np.tile(probe_views.UNCOVERED_COLOUR, (int(mask.sum()), 1)))
        np.testing.assert_array_equal(marked[~mask], display[~mask])

    def test_probe_pixels_are_the_nonzero_pixels_of_probe_centres(self):
        centres = np.zeros((4, 5, 1))
        centres[1, 3] = 2.0
        centres[0, 0] = 1.0
        xs, ys = probe_views.probe_pixels(centres)
        self.assertEqual(sorted(zip(xs.tolist(), ys.tolist())), [(0, 0), (3, 1)])


class MarkdownTableTest(unittest.TestCase):
    def test_a_pipe_table_becomes_an_html_table_with_escaped_cells(self):
        page = html_report.markdown_table_html("| method | relMSE |\n|---|--:|\n| a<b | 0.5 |\n| c | 1 |\n")
        self.assertEqual(page, "<table><thead><tr><th>method</th><th>relMSE</th></tr></thead><tbody>"
                               "<tr><td>a&lt;b</td><td>0.5</td></tr><tr><td>c</td><td>1</td></tr></tbody></table>")


class BadInputTest(unittest.TestCase):
    def test_a_folder_without_runs_exits_2_naming_it_and_writes_nothing(self):
        with tempfile.TemporaryDirectory() as folder:
            done = subprocess.run([PYTHON, str(SOURCE / "analysis/report.py"), folder], capture_output=True, text=True, timeout=60)
            self.assertEqual(done.returncode, 2, done.stderr)
            self.assertIn(f"error: {folder}: no runs", done.stderr)
            self.assertEqual(os.listdir(folder), [], "no report folder, no staging folder left")

    def test_a_malformed_region_exits_2(self):
        with tempfile.TemporaryDirectory() as folder:
            done = subprocess.run([PYTHON, str(SOURCE / "analysis/report.py"), folder, "--region", "1,2,3"], capture_output=True,
                                  text=True, timeout=60)
            self.assertEqual(done.returncode, 2)
            self.assertIn("--region 1,2,3: expected X,Y,WIDTH,HEIGHT", done.stderr)


@unittest.skipUnless(os.environ.get("GIBENCH_BINARY"), "needs GIBENCH_BINARY (ctest sets it) to make real runs")
class ReportOfRealRunsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.TemporaryDirectory()
        cls.root = pathlib.Path(cls.folder.name)
        cls.results = cls.root / "results"
        make_fixture(cls.results)
        cls.runs = results_reader.read_runs(cls.results)

    @classmethod
    def tearDownClass(cls):
        cls.folder.cleanup()

    def test_the_error_maps_average_to_the_relmse_gibench_measured(self):
        with tempfile.TemporaryDirectory() as out:
            (grid,) = image_grid.build_image_grids(self.runs, out)
        self.assertEqual(grid.scene, "cornell_box")
        self.assertEqual([entry["label"] for entry in grid.comparison], ["reference", "dense_grid", "mamba", "path_traced"])
        for run in self.runs:
            measured = run.metrics["error"]["total"]["relmse"]
            self.assertAlmostEqual(float(np.mean(grid.error_maps[run.method])), measured, delta=1e-6 * measured, msg=run.method)

    def test_probe_views_count_the_probes_in_view(self):
        (mamba,) = [run for run in self.runs if run.method == "mamba"]
        centres = exr_io.read_layer(mamba.folder / "image.exr", "probe_centres")
        with tempfile.TemporaryDirectory() as out:
            figures = probe_views.build_probe_views(self.runs, out, [])
            by_run = {f["path"]: f for f in figures}
            self.assertEqual(sorted(by_run), ["figures/probe_views_fixture_dense_grid.png", "figures/probe_views_fixture_mamba.png"],
                             "the probe caches' runs, not path tracing's")
            caption = by_run["figures/probe_views_fixture_mamba.png"]["caption"]
            self.assertGreater(centres.sum(), 0)
            self.assertIn(f"the {int(centres.sum())} probes in view", caption)
            self.assertNotIn("probes in view", by_run["figures/probe_views_fixture_dense_grid.png"]["caption"], "no probe_views layers")

    def stub_paper_outputs(self):
        """A stand-in for paper_outputs in sys.modules while the block runs: one plot and one table."""
        results = self.results

        def build_figures_and_tables(results_dir, out_dir):
            out_dir = pathlib.Path(out_dir)
            (out_dir / "tables").mkdir()
            (out_dir / "tables" / "t.md").write_text("| method | x |\n|---|---|\n| mamba | 1.5 |\n")
            shutil.copy(results / "fixture" / "mamba" / "image.png", out_dir / "plot.png")
            return {"runs_csv": "runs.csv", "figures": [{"path": "plot.png", "pdf": None, "caption": "stub plot", "scene": "cornell_box",
                                                         "kind": "curve"}],
                    "tables": [{"markdown": "tables/t.md", "latex": None, "caption": "stub table", "kind": "equal_time"}]}

        stub = types.ModuleType("paper_outputs")
        stub.build_figures_and_tables = build_figures_and_tables
        return unittest.mock.patch.dict(sys.modules, {"paper_outputs": stub})

    def test_the_page_shows_what_the_analysis_module_returns(self):
        out = self.root / "stub_report"
        with self.stub_paper_outputs():
            self.assertEqual(report.main([str(self.results), "--out", str(out), "--region", "4,4,8,8"]), 0)
        page = (out / "index.html").read_text()
        self.assertIn('<img src="plot.png" alt="curve">', page)
        self.assertIn("<figcaption>stub plot</figcaption>", page)
        self.assertIn("<tr><td>mamba</td><td>1.5</td></tr>", page)
        self.assertIn("Zoomed crops: (4, 4) 8x8.", page)
        self.assertEqual([p.name for p in out.parent.iterdir() if p.name.startswith(".")], [], "no staging folder left")

    def test_an_unreadable_image_exits_2_naming_it_and_leaves_the_old_report(self):
        results = self.root / "damaged"
        shutil.copytree(self.results, results)
        out = results / "report"
        out.mkdir()
        (out / "index.html").write_text("the old report")
        image = results / "fixture" / "dense_grid" / "image.exr"
        image.write_bytes(image.read_bytes()[:200])
        with self.stub_paper_outputs(), unittest.mock.patch("sys.stderr", new_callable=io.StringIO) as stderr:
            self.assertEqual(report.main([str(results)]), 2)
        self.assertRegex(stderr.getvalue(), f"^error: {re.escape(str(image))}: cannot read image: ")
        self.assertEqual((out / "index.html").read_text(), "the old report")
        self.assertEqual(sorted(p.name for p in results.iterdir()), ["fixture", "references", "report"], "no staging folder left")

    def test_gibench_report_writes_a_page_that_chromium_loads_whole(self):
        out = self.root / "report"
        done = gibench("report", str(self.results), "--out", str(out))
        self.assertIn(f"wrote {out / 'index.html'}", done.stdout)
        page = (out / "index.html").read_text()
        sources = re.findall(r'(?:src|href)="([^"#][^"]*)"', page)
        self.assertTrue(sources)
        for source in sources:
            self.assertNotRegex(source, r"^(https?:|//|/)", "every asset is a relative path inside the report")
            self.assertTrue((out / source).is_file(), source)
        self.assertIn('class="ab-slider"', page)

        profile = self.root / "chromium-profile"
        checked = out / "check.html"
        checked.write_text(page.replace("</body>", f"<script>{CHECK_SCRIPT}</script></body>"))
        screenshot = self.root / "screenshot.png"
        why = "no chromium on PATH (Debian package chromium)"
        if CHROMIUM is not None:
            done = chromium("--dump-dom", f"--screenshot={screenshot}", "--window-size=1280,2000", checked.as_uri(), profile=profile)
            dom = done.stdout
            # Chromium that runs at all dumps the page, whatever its scripts do.
            why = "" if "<html" in dom else f"chromium dumped no page (exit {done.returncode}): {done.stderr[-500:]}"
        if why:
            chromium_unavailable.append(why)
            self.skipTest(why)
        match = re.search(r'<pre id="load-check">(.*?)</pre>', dom, re.S)
        self.assertIsNotNone(match, dom[-2000:])
        result = json.loads(html.unescape(match.group(1)))
        images = result["images"]
        expected = set(re.findall(r'<img src="([^"]+)"', page))
        self.assertEqual({i["src"] for i in images}, expected)
        self.assertEqual([i["src"] for i in images if not i["loaded"]], [], "images or plots that did not load")
        plots = {f["path"] for f in json.loads((out / "outputs.json").read_text())["figures"]}
        self.assertTrue(plots and plots <= expected, "every plot of paper_outputs is on the page")
        self.assertTrue(any("image_grid_" in s for s in expected) and any("probe_views_" in s for s in expected), expected)
        compare = result["compare"]
        self.assertEqual(compare["clipBefore"], "inset(0px 0px 0px 50%)")
        self.assertEqual(compare["clipAfter"], "inset(0px 0px 0px 25%)")
        self.assertEqual(compare["transformA"], compare["transformB"], "A and B share one zoom")
        scale = float(re.search(r"scale\(([0-9.]+)\)", compare["transformA"]).group(1))
        self.assertAlmostEqual(scale, math.e, places=3)

        self.assertGreater(screenshot.stat().st_size, 0)
        pixels = exr_io.read_layer(screenshot, "total")
        self.assertEqual(pixels.shape[:2], (2000, 1280))
        colours = np.unique(np.round(pixels.reshape(-1, pixels.shape[2]) * 255).astype(int), axis=0)
        self.assertGreater(len(colours), 100, "a page of images and plots, not a blank one")


if __name__ == "__main__":
    result = unittest.main(exit=False).result
    if not result.wasSuccessful():
        sys.exit(1)
    if chromium_unavailable:
        print(f"SKIP: headless Chromium cannot run here: {chromium_unavailable[0]}")
        sys.exit(SKIP_CODE)
    sys.exit(0)
