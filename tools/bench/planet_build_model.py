#!/usr/bin/env python3
"""The scale model of a planet build (docs/planet-build-model.md) from measured shard costs.

Reads cluster_build_bench.py's JSON (its "Dask, 1 worker x 1 thread" run: the finest level's
shard tasks' CPU seconds, every level's shard bytes per patch, and the run's wall seconds per
CPU second, Dask's overhead included) and prints, for a planar region build of a raster of --width x --height
samples (default SRTM 1" global, 1,296,001 x 648,001) in 129-sample patches and shards of
16 x 16 patches: the tasks per level, core-hours, bytes written and wall time on 1, 64 and
1,024 workers. Rerun with:
  python3 tools/bench/planet_build_model.py out/bench/cluster-build-bench.json
"""
import argparse
import json
import math


def ceil_div(a, b):
    return -(-a // b)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bench", help="cluster-build-bench.json")
    parser.add_argument("--width", type=int, default=1_296_001)
    parser.add_argument("--height", type=int, default=648_001)
    parser.add_argument("--patch-quads", type=int, default=128)
    parser.add_argument("--shard-patches", type=int, default=16)
    parser.add_argument("--bytes-per-patch", type=float, nargs="*", default=[],
                        help="other measured bytes per patch to model (e.g. real DEMs')")
    args = parser.parse_args()

    bench = json.load(open(args.bench))
    run = next(r for r in bench["runs"] if r["run"] == "Dask, 1 worker x 1 thread")
    # A planet's tasks are nearly all full shards: the finest level's cost per task, and the
    # run's wall per CPU second (one worker: tasks one after another, Dask's overhead in it).
    finest_run = run["levels"][0]
    tasks = finest_run["tasks"]
    cpu_per_task = finest_run["taskCpuSeconds"] / tasks
    wall_per_cpu = run["wallSeconds"] / sum(level["taskCpuSeconds"] for level in run["levels"])
    wall_per_task = cpu_per_task * wall_per_cpu
    patches = sum(level["patches"] for level in run["levels"])
    bytes_per_patch = sum(level["shardBytes"] for level in run["levels"]) / patches

    # The layout (PyramidLayout): finest patches ceil((W - 1) / q), each coarser level half.
    px = max(1, ceil_div(args.width - 1, args.patch_quads))
    py = max(1, ceil_div(args.height - 1, args.patch_quads))
    finest = math.ceil(math.log2(max(px, py)))
    levels = []
    for level in range(finest, -1, -1):
        step = 1 << (finest - level)
        lx, ly = ceil_div(px, step), ceil_div(py, step)
        sx, sy = ceil_div(lx, args.shard_patches), ceil_div(ly, args.shard_patches)
        levels.append((level, lx * ly, sx * sy))
    all_tasks = sum(s for _, _, s in levels)
    all_patches = sum(p for _, p, _ in levels)
    critical_path = len(levels) * wall_per_task  # one task per level after the map

    print(f"Measured ({bench['source']}, {bench['machine']}, {bench['date']}): "
          f"{tasks} finest shard tasks of {finest_run['patches'] // tasks} patches, "
          f"{cpu_per_task:.2f} CPU s and {wall_per_task:.2f} s wall per task on 1 worker x 1 "
          f"thread, {bytes_per_patch / 1024:.1f} KiB per patch.")
    print()
    print(f"Raster {args.width:,} x {args.height:,}: {len(levels)} levels, finest "
          f"{px:,} x {py:,} patches; {all_patches:,} patches and {all_tasks:,} shard tasks "
          f"({levels[0][2]:,} at the finest level).")
    print()
    print("| | value |")
    print("|---|---|")
    print(f"| core-hours (CPU s per task x tasks) | {cpu_per_task * all_tasks / 3600:,.0f} |")
    for label, per_patch in [("bytes written (this terrain's KiB per patch)", bytes_per_patch)] + [
            (f"bytes written at {b / 1024:.1f} KiB per patch", b) for b in args.bytes_per_patch]:
        print(f"| {label} | {per_patch * all_patches / 1e12:,.2f} TB |")
    for workers in (1, 64, 1024):
        rounds = sum(ceil_div(s, workers) for _, _, s in levels)
        wall = rounds * wall_per_task
        print(f"| wall on {workers:,} worker{'s' if workers > 1 else ''} | "
              f"{wall / 3600:,.1f} h ({rounds:,} rounds of a task; the levels' chain alone "
              f"{critical_path:.0f} s) |")


if __name__ == "__main__":
    main()
