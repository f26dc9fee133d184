#!/usr/bin/env python3
"""Checks fuzz_report.py on the logs of a made-up run of two targets, one at 390 inputs a
second and one at 3 (fuzz-dem-tiff's rate while its corpus held inputs near the 2 GiB decode
limit): the JSON gives both targets' executions and rates and names the slow one, the run
still passes (a slow target is a warning), and a finding still fails it."""
import argparse
import json
import os
import subprocess
import sys
import tempfile

STATS = """INFO: Seed: 1
#2\tINITED cov: 120 ft: 200 corp: 2/1024b exec/s: 0 rss: 40Mb
#{runs}\tDONE   cov: 130 ft: 220 corp: 5/2048b lim: 4 exec/s: {rate} rss: 60Mb
Done {runs} runs in 15 second(s)
stat::number_of_executed_units: {runs}
stat::average_exec_per_sec:     {rate}
stat::new_units_added:          3
stat::slowest_unit_time_sec:    {slowest}
stat::peak_rss_mb:              60
"""


def write_target(logs, findings, name, runs, rate, slowest, finding=None):
    with open(os.path.join(logs, name + ".log"), "w") as f:
        f.write(STATS.format(runs=runs, rate=rate, slowest=slowest))
    with open(os.path.join(logs, name + ".rc"), "w") as f:
        f.write("1\n" if finding else "0\n")
    with open(os.path.join(logs, name + ".ns"), "w") as f:
        f.write(str(15 * 10**9) + "\n")
    os.makedirs(os.path.join(findings, name), exist_ok=True)
    if finding:
        open(os.path.join(findings, name, finding), "w").close()


def run_report(script, work, targets):
    out = os.path.join(work, "report.json")
    done = subprocess.run(
        [sys.executable, script, "--logs", os.path.join(work, "logs"), "--findings",
         os.path.join(work, "findings"), "--seconds", "15", "--targets", *targets, "-o", out],
        capture_output=True, text=True)
    with open(out) as f:
        return done, json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--script", required=True, help="tools/fuzz/fuzz_report.py")
    args = parser.parse_args()
    problems = []
    with tempfile.TemporaryDirectory() as work:
        logs, findings = os.path.join(work, "logs"), os.path.join(work, "findings")
        os.makedirs(logs)
        write_target(logs, findings, "dem-png", runs=5850, rate=390, slowest=0)
        write_target(logs, findings, "dem-tiff", runs=45, rate=3, slowest=2)
        done, report = run_report(args.script, work, ["dem-png", "dem-tiff"])
        by_name = {t["target"]: t for t in report["targets"]}
        if done.returncode != 0:
            problems.append(f"a slow target failed the run (exit {done.returncode})")
        if report["slow_targets"] != ["fuzz-dem-tiff"]:
            problems.append(f"slow_targets is {report['slow_targets']}, not ['fuzz-dem-tiff']")
        for name, runs, rate, slow in (("fuzz-dem-png", 5850, 390, False),
                                       ("fuzz-dem-tiff", 45, 3, True)):
            t = by_name[name]
            got = (t["executions"], t["executions_per_s"], t["slow"])
            if got != (runs, rate, slow):
                problems.append(f"{name}: executions, executions_per_s, slow are {got}, "
                                f"not {(runs, rate, slow)}")
        if by_name["fuzz-dem-tiff"]["slowest_input_s"] != 2:
            problems.append("fuzz-dem-tiff: slowest_input_s is not 2")
        if "fuzz-dem-tiff: warning: 3 inputs a second" not in done.stderr:
            problems.append(f"no warning naming fuzz-dem-tiff on stderr: {done.stderr!r}")
        if "fuzz-dem-png: warning" in done.stderr:
            problems.append("a warning for fuzz-dem-png, which ran 390 a second")

        write_target(logs, findings, "dem-asc", runs=9000, rate=600, slowest=0,
                     finding="crash-0123")
        done, report = run_report(args.script, work, ["dem-png", "dem-asc"])
        if done.returncode != 1 or report["findings"] != 1:
            problems.append(f"a finding: exit {done.returncode}, findings {report['findings']}")
    for p in problems:
        print("check_fuzz_report:", p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
