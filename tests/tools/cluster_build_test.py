#!/usr/bin/python3
"""terrain-build-cluster on a Dask LocalCluster of 2 worker processes, started and stopped by
the driver, as a user runs it (tools/cluster/terrain-build-cluster):

  - the pyramid it builds is the single-process build's, file for file, byte for byte (the
    manifest's build.seconds aside);
  - a worker process killed while it runs a task of 4 shards (TERRAIN_CLUSTER_FAULT=kill: the
    task kills its own worker the first time, as a lost machine would) is recovered by Dask,
    and the pyramid is still identical: tasks of several shards build the same files;
  - a task that fails (a source the worker cannot open) fails the build with terrain-build's
    message naming the shard and the file, exit status 1, and no pyramid or manifest;
  - a finest shard of the built-in planet (planet:, 2^21 + 1 × 2^20 + 1 samples) stays within
    --memory (peak RSS), as a planar pyramid and as a globe;
  - a globe pyramid of a region of the planet, built on the cluster, is the single-process
    region build's (terrain-build --globe --by-shards), file for file.

Deterministic: the faults are injected by shard, not by timing. Needs Debian's
python3-distributed (scripts/setup.sh). Usage:
  cluster_build_test.py --terrain-build BUILD/tools/terrain-build/terrain-build
                        --driver tools/cluster/terrain-build-cluster --work DIR
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

SOURCE = "procedural:width=1100,height=900,seed=7"
OPTIONS = ["--shard-patches", "3", "--patch-size", "65"]
GLOBE_SOURCE = "planet:seed=4,level=9,west=10,south=45,east=11,north=46"
# Every level above the finest nested: the carries' intervals cross processes too.
GLOBE_OPTIONS = ["--globe", "--shard-patches", "4", "--patch-size", "65", "--measured-levels", "0"]


def pyramid_files(folder):
    files = {}
    for path in sorted(Path(folder).rglob("*")):
        if not path.is_file():
            continue
        data = path.read_bytes()
        if path.name == "manifest.json":
            manifest = json.loads(data)
            del manifest["build"]["seconds"]
            data = json.dumps(manifest, sort_keys=True).encode()
        files[str(path.relative_to(folder))] = data
    return files


def expect_same(reference, built, failures, what):
    a, b = pyramid_files(reference), pyramid_files(built)
    if a.keys() != b.keys():
        failures.append(f"{what}: files differ: {sorted(set(a) ^ set(b))[:5]}")
        return
    different = [name for name in a if a[name] != b[name]]
    if different:
        failures.append(f"{what}: {len(different)} files differ, first {different[0]}")
    else:
        print(f"ok: {what}: {len(a)} files identical to the single-process build")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--terrain-build", required=True)
    parser.add_argument("--driver", required=True)
    parser.add_argument("--work", required=True)
    args = parser.parse_args()
    work = Path(args.work)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    failures = []

    def driver(output, env=None, extra=(), source=SOURCE, options=OPTIONS):
        command = ["/usr/bin/python3", args.driver, source, "-o", str(work / output),
                   "--workers", "2", "--terrain-build", args.terrain_build, "--json",
                   *options, *extra]
        return subprocess.run(command, capture_output=True, text=True,
                              env={**os.environ, **(env or {})}, timeout=600)

    subprocess.run([args.terrain_build, SOURCE, "-o", str(work / "single"), "-q", *OPTIONS],
                   check=True)

    run = driver("cluster", extra=["--shards-per-task", "1"])
    if run.returncode != 0:
        failures.append(f"cluster build failed: {run.stderr[-2000:]}")
    else:
        summary = json.loads(run.stdout)
        if summary["tasks"] < 20:
            failures.append(f"only {summary['tasks']} tasks: the test wants a real graph")
        expect_same(work / "single", work / "cluster", failures, "2 workers")

    marker = work / "killed-once"
    # The finest level of 1100 x 900 samples in 65-sample patches is 5 (18 x 15 patches);
    # shard 5/2/2 is in the middle of its 6 x 5 shards.
    run = driver("recovered", {"TERRAIN_CLUSTER_FAULT": f"kill:5/2/2:{marker}"},
                 ["--shards-per-task", "4"])
    if not marker.exists():
        failures.append("the kill fault never fired (shard 5/2/2 not run?)")
    if run.returncode != 0:
        failures.append(f"a killed worker was not recovered: {run.stderr[-2000:]}")
    else:
        summary = json.loads(run.stdout)
        if summary["tasks"] >= summary["shards"]:
            failures.append(f"{summary['tasks']} tasks for {summary['shards']} shards: not batched")
        expect_same(work / "single", work / "recovered", failures,
                    "a worker killed mid-build, 4 shards a task")

    run = driver("failed", {"TERRAIN_CLUSTER_FAULT": "fail:5/1/1"}, ["--shards-per-task", "1"])
    message = run.stderr
    if run.returncode != 1:
        failures.append(f"a failed task gave exit status {run.returncode}, not 1")
    if "shard 5/1/1 failed" not in message or "procedural" not in message:
        failures.append(f"a failed task's message does not name the shard and the source:\n{message}")
    if (work / "failed").exists() or (work / "failed.parts" / "manifest.json").exists():
        failures.append("a failed build left a pyramid or a manifest")
    if not failures:
        print("ok: a failed task fails the build, names the shard, writes no manifest")

    # A globe: the shards of the cube-sphere near a 1° region of the planet, their children
    # before them, on the cluster, against one process building them in order.
    subprocess.run([args.terrain_build, GLOBE_SOURCE, "-o", str(work / "globe-single"), "-q",
                    "--by-shards", *GLOBE_OPTIONS], check=True)
    run = driver("globe-cluster", extra=["--shards-per-task", "2"], source=GLOBE_SOURCE,
                 options=GLOBE_OPTIONS)
    if run.returncode != 0:
        failures.append(f"globe cluster build failed: {run.stderr[-2000:]}")
    else:
        summary = json.loads(run.stdout)
        if summary["tiling"] != "globe" or summary["tasks"] < 10:
            failures.append(f"a globe build of {summary['tasks']} tasks: the test wants a graph")
        expect_same(work / "globe-single", work / "globe-cluster", failures, "a globe, 2 workers")

    # Bounded memory at any size: one finest shard of the planet, 2^21 + 1 × 2^20 + 1 samples.
    budget = 256 << 20
    wide = "planet:seed=1"
    plan = subprocess.run([args.terrain_build, wide, "-o", str(work / "wide"), "--plan", "--json",
                           "--memory", str(budget)], capture_output=True, text=True)
    if plan.returncode != 0:
        failures.append(f"planning the planet's build failed: {plan.stderr}")
    else:
        finest = json.loads(plan.stdout)["finestLevel"]
        shard = subprocess.run([args.terrain_build, wide, "-o", str(work / "wide"), "--shard",
                                f"{finest}/300/200", "--memory", str(budget), "--json"],
                               capture_output=True, text=True)
        if shard.returncode != 0:
            failures.append(f"a shard of the planet failed: {shard.stderr}")
        else:
            rss = json.loads(shard.stdout)["peakRssBytes"]
            if rss > budget:
                failures.append(f"a shard of the planet peaked at {rss >> 20} MiB, over --memory "
                                f"{budget >> 20} MiB")
            else:
                print(f"ok: a shard of the 2^21 + 1 × 2^20 + 1 planet peaked at {rss >> 20} MiB "
                      f"(--memory {budget >> 20} MiB)")

    # The same as a globe: a finest shard at 27° N (face 0, 8 × 8 patches of face level 13)
    # reads the planet's samples around it block by block, within --memory.
    globe_budget = 256 << 20
    shard = subprocess.run([args.terrain_build, wide, "--globe", "-o", str(work / "wide-globe"),
                            "--shard", "16/512/256", "--shard-patches", "8", "--memory",
                            str(globe_budget), "--json"], capture_output=True, text=True)
    if shard.returncode != 0:
        failures.append(f"a globe shard of the planet failed: {shard.stderr}")
    else:
        summary = json.loads(shard.stdout)
        rss = summary["peakRssBytes"]
        if rss > globe_budget or summary["patches"] != 64:
            failures.append(f"a globe shard of the planet: {summary['patches']} patches, peak "
                            f"{rss >> 20} MiB against --memory {globe_budget >> 20} MiB")
        else:
            print(f"ok: a globe shard of the planet (64 patches) peaked at {rss >> 20} MiB "
                  f"(--memory {globe_budget >> 20} MiB)")

    for failure in failures:
        print(f"FAILED: {failure}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
