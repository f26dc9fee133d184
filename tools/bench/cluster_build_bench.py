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

--globe benchmarks a globe pyramid's region build instead (PyramidShards.h), on a 1° box of the
built-in planet at 1.24" (planet:seed=1,level=11,west=10,south=45,east=11,north=46, 8.5
million samples):
  terrain-build SRC --globe -o P --threads 2                          (the whole build)
  terrain-build SRC --globe -o P --threads 2 --by-shards              (measured: all levels)
  terrain-build SRC --globe -o P --threads 2 --by-shards --measured-levels 2  (as a planet's)
  terrain-build-cluster ... --measured-levels 2 --workers 1 --threads-per-task 1
  terrain-build-cluster ... --measured-levels 2 --workers 2 --threads-per-task 1
The first by-shards run must equal the whole build byte for byte; the Dask runs must equal
the third. Writes OUT/cluster-build-bench-globe.json and .md.
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


def same_files(a, b):
    """Every file the same, the manifest's build.seconds aside."""
    names = sorted(p.relative_to(a) for p in Path(a).rglob("*") if p.is_file())
    if names != sorted(p.relative_to(b) for p in Path(b).rglob("*") if p.is_file()):
        return False
    for n in names:
        if n.name == "manifest.json":
            ma, mb = (json.loads((Path(x) / n).read_text()) for x in (a, b))
            del ma["build"]["seconds"], mb["build"]["seconds"]
            if ma != mb:
                return False
        elif not filecmp.cmp(Path(a) / n, Path(b) / n, shallow=False):
            return False
    return True


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
    parser.add_argument("--source", default=None,
                        help="default procedural:size=16385, with --globe a box of the planet")
    parser.add_argument("--globe", action="store_true", help="a globe pyramid's region build")
    parser.add_argument("--runs", default=None,
                        help="comma-separated run indices to run besides run 0 (default: all)")
    args = parser.parse_args()
    if args.source is None:
        args.source = ("planet:seed=1,level=11,west=10,south=45,east=11,north=46" if args.globe
                       else "procedural:size=16385")
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
    # Which earlier run each must equal (the whole build's, for a planar pyramid).
    reference = [0] * len(runs)
    if args.globe:
        globe = ["--globe"]
        nested = ["--measured-levels", "2"]
        runs = [
            ("whole build, 2 threads", [build, *globe, "--threads", "2"]),
            ("--by-shards, 2 threads", [build, *globe, "--threads", "2", "--by-shards"]),
            ("--by-shards, 2 threads, --measured-levels 2",
             [build, *globe, "--threads", "2", "--by-shards", *nested]),
            ("Dask, 1 worker x 1 thread, --measured-levels 2",
             [*dask, *globe, *nested, "--workers", "1", "--threads-per-task", "1", "--json"]),
            ("Dask, 2 workers x 1 thread, --measured-levels 2",
             [*dask, *globe, *nested, "--workers", "2", "--threads-per-task", "1", "--json"]),
        ]
        reference = [0, 0, 2, 2, 2]
    if args.runs is not None:
        asked = {0, *(int(i) for i in args.runs.split(","))}
        chosen = sorted(asked | {reference[i] for i in asked})  # and what they must equal
        renumbered = {old: new for new, old in enumerate(chosen)}
        reference = [renumbered[reference[i]] for i in chosen]
        runs = [runs[i] for i in chosen]
    kept = set(reference)
    results = []
    for index, (name, command) in enumerate(runs):
        pyramid = work / f"p{index}"
        # The driver's INPUT comes first: argparse would take an option's value for it.
        at = 4 if command[0] == "/usr/bin/python3" else len(command)
        wall, cpu, rss, stdout = run(
            [*command[:at], args.source, "-o", str(pyramid), *command[at:], "-q"],
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
        against = reference[index]
        entry["identicalTo"] = runs[against][0]
        entry["shardsIdenticalToWholeBuild"] = index == against or (
            same_files(work / f"p{against}", pyramid) if args.globe
            else same_shards(work / f"p{against}", pyramid))
        summary_json = stdout if "--json" in command else None
        if args.globe and summary_json is None:
            entry["levels"] = [
                {"level": level, "maxErrorM": m["maxError"], "presentPatches": m["presentPatches"]}
                for level, m in enumerate(json.loads((pyramid / "manifest.json").read_text())
                                          ["levels"]) if m["presentPatches"]]
        results.append(entry)
        print(f"{name}: {wall:.1f} s wall, {cpu:.1f} s CPU, peak RSS {rss >> 20} MiB, "
              f"identical to '{runs[against][0]}' {entry['shardsIdenticalToWholeBuild']}",
              flush=True)
        if index not in kept:
            shutil.rmtree(pyramid)
    for index in kept:
        shutil.rmtree(work / f"p{index}", ignore_errors=True)

    report = {"tool": "cluster_build_bench", "source": args.source,
              "machine": f"{platform.node()} ({os.cpu_count()} CPUs)",
              "date": time.strftime("%Y-%m-%d %H:%M"), "runs": results}
    name = "cluster-build-bench-globe" if args.globe else "cluster-build-bench"
    (out / f"{name}.json").write_text(json.dumps(report, indent=2))
    lines = [f"# Region build: one process against Dask workers ({args.source})", "",
             f"{report['machine']}, {report['date']}.", "",
             "| run | wall s | CPU s | peak RSS MiB | largest task RSS MiB | tasks | shards | "
             "identical to its reference |",
             "|---|---|---|---|---|---|---|---|"]
    for r in results:
        task_rss = r.get("largestTaskPeakRssBytes")
        lines.append(f"| {r['run']} | {r['wallSeconds']:.1f} | {r['cpuSeconds']:.1f} | "
                     f"{r['peakRssBytes'] >> 20} | "
                     f"{task_rss >> 20 if task_rss else '-'} | {r.get('tasks', '-')} | "
                     f"{r.get('shards', '-')} | "
                     f"{'yes' if r['shardsIdenticalToWholeBuild'] else 'NO'} |")
    (out / f"{name}.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
