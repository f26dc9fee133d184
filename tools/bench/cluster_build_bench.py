#!/usr/bin/python3
"""Region build benchmark: one process against Dask workers on the 16K procedural terrain.

Runs, one after another on this machine, the same pyramid of procedural:size=16385 (16,385²
float32 samples, 2 cores' worth of work each):
  terrain-build SRC -o P --threads 2                        (the whole build, in bands)
  terrain-build SRC -o P --threads 2 --by-shards            (one shard after another)
  terrain-build-cluster SRC -o P --workers 1 --threads-per-task 2   (Dask, 1 worker)
  terrain-build-cluster SRC -o P --workers 2 --threads-per-task 1   (Dask, 2 workers)
  terrain-build-cluster SRC -o P --workers 1 --threads-per-task 1   (1 worker, 1 core)
  terrain-build-cluster SRC -o P --workers 2 --shards-per-task 4    (tasks of 4 shards)
  terrain-build-cluster SRC -o P --workers 2 --shards-per-task 16   (tasks of 16 shards)
(the Dask runs above the last two at one shard a task), recording wall seconds, CPU seconds of the whole process tree and its largest peak RSS
(os.wait4), checks that every pyramid's shards are the whole build's byte for byte, and keeps
the per-level shard task costs (the 2-worker run's) for the scale model in
docs/planet-build-model.md. Writes OUT/cluster-build-bench.json and .md. Rerun with:
  /usr/bin/python3 tools/bench/cluster_build_bench.py --build build --out out/bench
--runs 1,3,5 runs only those (0-based, in the order above; the whole build, run 0, always
runs: it is the reference the others must equal).
"""
import argparse
import filecmp
import json
import os
import platform
import shutil
import time
from pathlib import Path

from measured_run import run  # (wall s, CPU s, peak RSS bytes, stdout)

REPO = Path(__file__).resolve().parents[2]


def same_shards(a, b):
    names = sorted(p.relative_to(a) for p in Path(a).rglob("*.exr"))
    if names != sorted(p.relative_to(b) for p in Path(b).rglob("*.exr")):
        return False
    return all(filecmp.cmp(Path(a) / n, Path(b) / n, shallow=False) for n in names)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=str(REPO / "build"))
    parser.add_argument("--out", default=str(REPO / "out" / "bench"))
    parser.add_argument("--source", default="procedural:size=16385")
    parser.add_argument("--runs", default=None,
                        help="comma-separated run indices to run besides run 0 (default: all)")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    work = out / "cluster-build-work"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir()
    build = str(Path(args.build) / "tools" / "terrain-build" / "terrain-build")
    driver = str(REPO / "tools" / "cluster" / "terrain-build-cluster")
    dask = ["/usr/bin/python3", driver, "--terrain-build", build]
    runs = [
        ("whole build, 2 threads", [build, "--threads", "2"]),
        ("--by-shards, 2 threads", [build, "--threads", "2", "--by-shards"]),
        ("Dask, 1 worker x 2 threads", [*dask, "--workers", "1", "--threads-per-task", "2",
                                        "--shards-per-task", "1", "--json"]),
        ("Dask, 2 workers x 1 thread", [*dask, "--workers", "2", "--threads-per-task", "1",
                                        "--shards-per-task", "1", "--json"]),
        ("Dask, 1 worker x 1 thread", [*dask, "--workers", "1", "--threads-per-task", "1",
                                       "--shards-per-task", "1", "--json"]),
        ("Dask, 2 workers x 1 thread, 4 shards a task",
         [*dask, "--workers", "2", "--threads-per-task", "1", "--shards-per-task", "4", "--json"]),
        ("Dask, 2 workers x 1 thread, 16 shards a task",
         [*dask, "--workers", "2", "--threads-per-task", "1", "--shards-per-task", "16",
          "--json"]),
    ]
    if args.runs is not None:
        chosen = {0, *(int(i) for i in args.runs.split(","))}
        runs = [entry for i, entry in enumerate(runs) if i in chosen]
    results = []
    for index, (name, command) in enumerate(runs):
        pyramid = work / f"p{index}"
        wall, cpu, rss, stdout = run([*command, args.source, "-o", str(pyramid), "-q"],
                                     work / f"p{index}.log")
        entry = {"run": name, "command": " ".join([*command, args.source, "-o", "P"]),
                 "wallSeconds": wall, "cpuSeconds": cpu, "peakRssBytes": rss,
                 "bytes": sum(p.stat().st_size for p in pyramid.rglob("*") if p.is_file())}
        if "--json" in command:
            summary = json.loads(stdout)
            entry["tasks"] = summary["tasks"]
            entry["shards"] = summary["shards"]
            entry["largestTaskPeakRssBytes"] = summary["largestTaskPeakRssBytes"]
            entry["levels"] = summary["levels"]
        entry["shardsIdenticalToWholeBuild"] = index == 0 or same_shards(work / "p0", pyramid)
        results.append(entry)
        print(f"{name}: {wall:.1f} s wall, {cpu:.1f} s CPU, peak RSS {rss >> 20} MiB, "
              f"identical {entry['shardsIdenticalToWholeBuild']}", flush=True)
        if index > 0:
            shutil.rmtree(pyramid)
    shutil.rmtree(work / "p0")

    report = {"tool": "cluster_build_bench", "source": args.source,
              "machine": f"{platform.node()} ({os.cpu_count()} CPUs)",
              "date": time.strftime("%Y-%m-%d %H:%M"), "runs": results}
    (out / "cluster-build-bench.json").write_text(json.dumps(report, indent=2))
    lines = [f"# Region build: one process against Dask workers ({args.source})", "",
             f"{report['machine']}, {report['date']}.", "",
             "| run | wall s | CPU s | peak RSS MiB | largest task RSS MiB | tasks | shards | "
             "identical |",
             "|---|---|---|---|---|---|---|---|"]
    for r in results:
        task_rss = r.get("largestTaskPeakRssBytes")
        lines.append(f"| {r['run']} | {r['wallSeconds']:.1f} | {r['cpuSeconds']:.1f} | "
                     f"{r['peakRssBytes'] >> 20} | "
                     f"{task_rss >> 20 if task_rss else '-'} | {r.get('tasks', '-')} | "
                     f"{r.get('shards', '-')} | "
                     f"{'yes' if r['shardsIdenticalToWholeBuild'] else 'NO'} |")
    (out / "cluster-build-bench.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
