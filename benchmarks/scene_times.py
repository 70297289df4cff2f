"""Wall time of every bundled scene on this machine: ``fsi run NAME`` as a user runs it
(results and plots), one after the other.

    python benchmarks/scene_times.py [--smoke] [--scenes NAME ...] [--update] [--out-root DIR]

Prints one JSON object: per scene its wall seconds, exit status (0 converged, 3 finished with
some window, frame or fill not converged), description, the machine's 1-minute load average
when it started (about 0 on a quiet machine; each busy core adds 1) and the commit it ran at;
the README's scene table and the documentation read the full run's
``docs/data/scene_times.json``. ``--update`` times only the scenes named by ``--scenes`` and
keeps the other scenes' entries of that file (a scene re-timed after a change, or on a quieter
machine). ``--smoke`` runs ``thesis-plate`` only (seconds).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from _report import DOCS_DATA, SMOKE_HELP, commit, emit, output_dir

from fsi.registry import PROCEDURES
from fsi.scene import bundled_scenes, load_scene

DOC_FIELDS = ("scenes", "total_seconds")
SMOKE_SCENES = ("thesis-plate",)


def run_scene(name: str, root: Path) -> dict:
    """Run bundled scene ``name`` into ``root/name``; its wall seconds, exit status, description."""
    scene = load_scene(name)
    load = os.getloadavg()[0]
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "fsi.cli", "run", name, "--out", str(root / name),
                           "--overwrite"], capture_output=True, text=True,
                          cwd=Path(__file__).resolve().parents[1])
    wall = time.perf_counter() - start
    if done.returncode not in (0, 3):
        sys.stderr.write(done.stderr[-2000:])
    return {"wall_seconds": round(wall, 1), "exit_code": done.returncode,
            "procedure": scene["scene"]["procedure"], "description": scene["scene"]["description"],
            "load_average": round(load, 2), "commit": commit()}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--smoke", action="store_true", help=SMOKE_HELP)
    parser.add_argument("--scenes", nargs="+", choices=bundled_scenes(), default=None)
    parser.add_argument("--update", action="store_true",
                        help="keep the other scenes' entries of docs/data/scene_times.json")
    parser.add_argument("--out-root", type=Path, default=None,
                        help="where the runs' folders go (default benchmarks/output/scenes)")
    args = parser.parse_args()
    names = args.scenes or (list(SMOKE_SCENES) if args.smoke else bundled_scenes())
    root = args.out_root or output_dir(args.smoke) / "scenes"
    kept = DOCS_DATA / "scene_times.json"
    if args.update and not (args.scenes and kept.exists()):
        parser.error("--update needs --scenes and an existing docs/data/scene_times.json")
    scenes = json.loads(kept.read_text())["scenes"] if args.update else {}
    for name in names:
        scenes[name] = run_scene(name, root)
        print(f"{name}: {scenes[name]['wall_seconds']} s, exit {scenes[name]['exit_code']}",
              file=sys.stderr, flush=True)
    scenes = {name: scenes[name] for name in sorted(scenes)}
    record = {"scenes": scenes, "total_seconds": round(sum(s["wall_seconds"] for s in
                                                            scenes.values()), 1),
              "procedures": sorted(PROCEDURES)}
    emit("scene_times", record, args.smoke)
    return 0 if all(s["exit_code"] in (0, 3) for s in scenes.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
