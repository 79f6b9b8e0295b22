#!/usr/bin/python3
"""The report of a results folder: figures, tables, image grids, probe views and one static HTML page.

usage: /usr/bin/python3 analysis/report.py RESULTS_DIR [--out OUT] [--region X,Y,W,H ...] [--layer LAYER]
       (or: gibench report RESULTS_DIR [--out OUT])

RESULTS_DIR is a results root (<experiment>/<run>/ and references/), an experiment folder or a run.
OUT (default RESULTS_DIR/report) gets, whole or not at all (it is built in a hidden folder beside it,
then renamed into place):
  index.html              the page (html_report.py): per scene an A/B comparison with a slider and
                          zoom, the image grid and probe views; the plots; the tables
  runs.csv, outputs.json, figures/, tables/
                          paper_outputs.build_figures_and_tables: the tidy runs table, the plots and
                          tables (Markdown and LaTeX)
  figures/image_grid_<scene>.{png,pdf}     image_grid.py: reference, methods at equal time, crops, error maps
  figures/probe_views_<run>.{png,pdf}     probe_views.py: probe positions and coverage, splatted probes
  images/<scene>/<n>.png             the grid's images, tone-mapped alike, for the A/B comparison
Regions (--region, repeatable) are zoomed in every grid; by default the best cache's worst square.
Bad input (no runs, an unreadable file, a region outside an image) prints "error: ..." naming it and
exits with code 2, leaving OUT as it was.
"""

import argparse
import os
import pathlib
import shutil
import sys

from input_error import InputError


def parse_region(text: str) -> tuple:
    try:
        values = tuple(int(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 4:
        raise InputError(f"--region {text}: expected X,Y,WIDTH,HEIGHT in pixels, e.g. 8,8,16,16")
    return values


def build(results_dir: pathlib.Path, out_dir: pathlib.Path, regions, layer: str) -> pathlib.Path:
    """Everything of the report into out_dir (an empty folder); the page's path."""
    import html_report
    import image_grid
    import paper_outputs
    import probe_views
    import results_reader

    runs = results_reader.read_runs(results_dir)
    outputs = paper_outputs.build_figures_and_tables(results_dir, out_dir)
    grids = image_grid.build_image_grids(runs, out_dir, regions, layer)
    probes = probe_views.build_probe_views(runs, out_dir, grids)
    title = f"{results_dir.resolve()}: {len(runs)} runs"
    return html_report.write_report(out_dir, title, outputs, grids, probes)


def replace_folder(staging: pathlib.Path, out_dir: pathlib.Path):
    """Moves the finished staging folder to out_dir, replacing what was there."""
    old = out_dir.with_name(f".{out_dir.name}.old-{os.getpid()}")
    if out_dir.exists():
        out_dir.rename(old)
    staging.rename(out_dir)
    shutil.rmtree(old, ignore_errors=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("results_dir", type=pathlib.Path)
    parser.add_argument("--out", type=pathlib.Path, help="report folder (default RESULTS_DIR/report)")
    parser.add_argument("--region", action="append", default=None, help="X,Y,WIDTH,HEIGHT in pixels: a crop of every grid")
    parser.add_argument("--layer", default="total", help="the image layer the grids compare (default total)")
    args = parser.parse_args(argv)
    out_dir = args.out or args.results_dir / "report"
    staging = out_dir.with_name(f".{out_dir.name}.staging-{os.getpid()}")
    try:
        regions = [parse_region(r) for r in args.region] if args.region else None
        if not args.results_dir.is_dir():
            raise InputError(f"{args.results_dir}: not a folder (expected a results root, an experiment folder or a run)")
        staging.mkdir(parents=True)
        index = build(args.results_dir, staging, regions, args.layer)
        replace_folder(staging, out_dir)
    except InputError as e:
        shutil.rmtree(staging, ignore_errors=True)
        print(f"error: {e}", file=sys.stderr)
        return 2
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    print(f"wrote {out_dir / index.name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
