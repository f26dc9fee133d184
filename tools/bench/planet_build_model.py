#!/usr/bin/env python3
"""The scale model of a planet build (docs/planet-build-model.md) from measured shard costs.

Reads cluster_build_bench.py's JSON (its "Dask, 1 worker x 1 thread" run: the finest level's
shard tasks' CPU seconds, every level's shard bytes per patch, and the run's wall seconds per
CPU second, Dask's overhead included) and prints, for a planar region build of a raster of --width x --height
samples (default SRTM 1" global, 1,296,001 x 648,001) in 129-sample patches and shards of
16 x 16 patches: the tasks per level, core-hours, bytes written and wall time on 1, 64 and
1,024 workers. Rerun with:
  python3 tools/bench/planet_build_model.py out/bench/cluster-build-bench.json

With --globe it reads cluster_build_bench.py --globe's JSON (its "Dask, 1 worker x 1 thread,
--measured-levels 2" run) and models the globe pyramid of a geographic source of
--spacing-arcsec (default 1", SRTM 1" global): face levels as globeFinestLevelFor decides
them, every patch of every level present, the finest level and the two above it measured at
the source's samples (each costing what the bench's level costs against its finest level),
the levels above nested (per patch, less each task's 0.35 s start, which a full shard's 256
patches amortise). Rerun with:
  python3 tools/bench/planet_build_model.py --globe out/bench/cluster-build-bench-globe.json
"""
import argparse
import json
import math


def ceil_div(a, b):
    return -(-a // b)


TASK_START_SECONDS = 0.35  # terrain-build's start (libraries), measured: docs/planet-build-model.md


def globe_model(args):
    bench = json.load(open(args.bench))
    run = next(r for r in bench["runs"]
               if r["run"] == "Dask, 1 worker x 1 thread, --measured-levels 2")
    levels = {entry["level"]: entry for entry in run["levels"]}
    finest_layout = max(levels)
    offset = 3  # layout levels above the faces (ManifestGlobe::kLevelOffset)
    finest = levels[finest_layout]
    cpu_per_finest_patch = finest["taskCpuSeconds"] / finest["patches"]
    wall_per_cpu = run["wallSeconds"] / sum(e["taskCpuSeconds"] for e in run["levels"])
    patches = sum(e["patches"] for e in run["levels"])
    bytes_per_patch = sum(e["shardBytes"] for e in run["levels"]) / patches
    nested = [e for layout, e in levels.items() if layout < finest_layout - 2]
    nested_cpu = sum(max(0.0, e["taskCpuSeconds"] - TASK_START_SECONDS * e["tasks"])
                     for e in nested)
    cpu_per_nested_patch = nested_cpu / max(1, sum(e["patches"] for e in nested))

    # globeFinestLevelFor at the equator on face 0: metres per unit face coordinate there is
    # pi/2 times the equatorial radius; the source's finest spacing is along the meridian.
    a, b2_over_a = 6378137.0, 6378137.0 * (1 - 0.00669437999014)
    spacing = min(math.radians(args.spacing_arcsec / 3600.0) * b2_over_a,
                  math.radians(args.spacing_arcsec / 3600.0) * a)
    face_finest = max(0, math.ceil(math.log2(math.pi / 2 * a / (args.patch_quads * spacing))
                                   - 1e-9))
    rows = []
    for face_level in range(face_finest, -1, -1):
        n = 1 << face_level
        level_patches = 6 * n * n
        shards = ceil_div(6 * n, args.shard_patches) * ceil_div(n, args.shard_patches)
        bench_level = levels.get(face_level - face_finest + finest_layout)
        if face_level >= face_finest - 2:
            # A pass over the source's samples: the bench's level against its finest level.
            ratio = bench_level["taskCpuSeconds"] / finest["taskCpuSeconds"]
            cpu = ratio * cpu_per_finest_patch * 6 * (1 << face_finest) ** 2
        else:
            cpu = cpu_per_nested_patch * level_patches + TASK_START_SECONDS * shards
        rows.append((face_level, level_patches, shards, cpu))
    all_patches = sum(r[1] for r in rows)
    all_tasks = sum(r[2] for r in rows)
    all_cpu = sum(r[3] for r in rows)
    # Carries: every patch below the faces' hands its parent its even samples; the per-quad
    # intervals only where the parent is nested (face levels up to face_finest - 2).
    half = args.patch_quads // 2
    evens_per_patch = (half + 1) ** 2 * 5 + 16
    intervals_per_patch = half * half * 8
    carry_bytes = sum(level_patches * (evens_per_patch + (intervals_per_patch
                                                         if face_level <= face_finest - 3 + 1
                                                         else 0))
                      for face_level, level_patches, _, _ in rows if face_level > 0)

    print(f"Measured ({bench['source']}, {bench['machine']}, {bench['date']}): a finest patch "
          f"{cpu_per_finest_patch:.3f} CPU s, a nested one {cpu_per_nested_patch:.4f} CPU s "
          f"(less {TASK_START_SECONDS} s a task), {bytes_per_patch / 1024:.1f} KiB per patch; "
          f"wall {wall_per_cpu:.2f} s per CPU s on 1 worker.")
    print()
    print(f"A geographic source of {args.spacing_arcsec}\" ({spacing:.1f} m along the meridian): "
          f"face levels 0 … {face_finest}, {all_patches:,} patches in {all_tasks:,} shard tasks "
          f"({rows[0][2]:,} at the finest level).")
    print()
    print("| face level | patches | shard tasks | CPU hours | how |")
    print("|---|---|---|---|---|")
    for face_level, level_patches, shards, cpu in rows:
        how = "measured" if face_level >= face_finest - 2 else "nested"
        print(f"| {face_level} | {level_patches:,} | {shards:,} | {cpu / 3600:,.1f} | {how} |")
    print()
    print("| | value |")
    print("|---|---|")
    print(f"| core-hours | {all_cpu / 3600:,.0f} |")
    print(f"| bytes written at {bytes_per_patch / 1024:.1f} KiB per patch | "
          f"{bytes_per_patch * all_patches / 1e12:,.2f} TB |")
    print(f"| carries (temporary): {evens_per_patch / 1024:.1f} KiB per patch below the faces', "
          f"{intervals_per_patch / 1024:.1f} KiB more under a nested parent | "
          f"{carry_bytes / 1e12:,.2f} TB |")
    for workers in (1, 64, 1024):
        wall = 0.0
        for face_level, level_patches, shards, cpu in rows:
            per_task = cpu / shards * wall_per_cpu
            wall += ceil_div(shards, workers) * per_task
        print(f"| wall on {workers:,} worker{'s' if workers > 1 else ''} | {wall / 3600:,.1f} h |")


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bench", help="cluster-build-bench.json")
    parser.add_argument("--globe", action="store_true",
                        help="model a globe pyramid from cluster-build-bench-globe.json")
    parser.add_argument("--spacing-arcsec", type=float, default=1.0,
                        help="with --globe: the source's sample spacing")
    parser.add_argument("--width", type=int, default=1_296_001)
    parser.add_argument("--height", type=int, default=648_001)
    parser.add_argument("--patch-quads", type=int, default=128)
    parser.add_argument("--shard-patches", type=int, default=16)
    parser.add_argument("--bytes-per-patch", type=float, nargs="*", default=[],
                        help="other measured bytes per patch to model (e.g. real DEMs')")
    args = parser.parse_args()
    if args.globe:
        globe_model(args)
        return

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
