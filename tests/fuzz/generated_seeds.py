#!/usr/bin/python3
"""Writes the seeds that are better generated than committed into OUT/<target>/:
fuzz_config: every run config of configs/ with its scene file inlined (the fuzzer's private folder
holds no scene files), and a config whose "frames" is 100,000 nested arrays (200 KB);
fuzz_obj: the shared Cornell box OBJ with its MTL, when the shared scenes are there.
Usage: generated_seeds.py OUT"""

import json
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
MTL_MARKER = "#--- model.mtl"  # fuzz_obj.cpp's kMtlMarker


def config_seeds(out):
    for config_file in sorted((ROOT / "configs").rglob("*.json")):
        config = json.loads(config_file.read_text())
        if "method" not in config or not isinstance(config.get("scene"), str):
            continue
        config["scene"] = json.loads((config_file.parent / config["scene"]).read_text())
        name = "_".join(config_file.relative_to(ROOT / "configs").with_suffix("").parts)
        (out / f"inlined_{name}.json").write_text(json.dumps(config))
    depth = 100_000
    nested = '{"frames": ' + "[" * depth + "]" * depth + ', "scene": {"shapes": [{"type": "quad"}]}, "method": {"name": "path_traced"}}'
    (out / "frames_nested_100000.json").write_text(nested)


def obj_seeds(out):
    scenes = pathlib.Path(os.environ.get("GIBENCH_SCENES") or ROOT.parent / "shared" / "scenes")
    obj = scenes / "cornell-box" / "CornellBox-Original.obj"
    if obj.exists():
        text = obj.read_text().replace("mtllib CornellBox-Original.mtl", "mtllib model.mtl")
        mtl = obj.with_suffix(".mtl").read_text()
        (out / "cornell_box_original").write_text(text + "\n" + MTL_MARKER + "\n" + mtl)


def main():
    out = pathlib.Path(sys.argv[1])
    for target, write in (("fuzz_config", config_seeds), ("fuzz_obj", obj_seeds)):
        (out / target).mkdir(parents=True, exist_ok=True)
        write(out / target)


if __name__ == "__main__":
    main()
