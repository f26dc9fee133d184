#!/usr/bin/env python3
"""Summarises a scripts/fuzz.sh run: per target, executions, coverage (libFuzzer's "cov",
edges, and "ft", features), corpus size, peak RSS and findings (crash-, leak-, timeout-,
oom- inputs), read from each target's log, exit status and findings folder. Writes JSON,
prints a table, and exits 1 when any target found something or did not finish cleanly.
A target that ran fewer than --min-exec-per-s inputs a second is named as slow (a warning,
not a failure): such a run explores almost nothing, as fuzz-dem-tiff did at 1 to 6 a second
while its corpus held inputs that each decoded near 2 GiB."""
import argparse
import json
import os
import re
import sys

FINDING_PREFIXES = ("crash-", "leak-", "timeout-", "oom-")


def read_target(name, logs, findings):
    log_path = os.path.join(logs, name + ".log")
    with open(log_path, errors="replace") as f:
        log = f.read()
    with open(os.path.join(logs, name + ".rc")) as f:
        exit_code = int(f.read().strip())
    stats = dict(re.findall(r"^stat::(\w+):\s+(\d+)", log, re.M))
    status_lines = re.findall(r"^#(\d+)\s+\w+\s+cov: (\d+) ft: (\d+) corp: (\d+)", log, re.M)
    last = status_lines[-1] if status_lines else ("0", "0", "0", "0")
    folder = os.path.join(findings, name)
    found = sorted(f for f in os.listdir(folder) if f.startswith(FINDING_PREFIXES)) \
        if os.path.isdir(folder) else []
    executions = int(stats.get("number_of_executed_units", last[0]))
    with open(os.path.join(logs, name + ".ns")) as f:
        seconds = int(f.read().strip()) / 1e9
    return {
        "target": "fuzz-" + name,
        "seconds": round(seconds, 1),
        "executions": executions,
        "executions_per_s": int(stats.get("average_exec_per_sec", 0)),
        "coverage_edges": int(last[1]),
        "coverage_features": int(last[2]),
        "corpus_inputs": int(last[3]),
        "new_inputs": int(stats.get("new_units_added", 0)),
        "peak_rss_mb": int(stats.get("peak_rss_mb", 0)),
        "slowest_input_s": int(stats.get("slowest_unit_time_sec", 0)),
        "findings": [os.path.join(folder, f) for f in found],
        "exit_code": exit_code,
        "log": log_path,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--logs", required=True)
    parser.add_argument("--findings", required=True)
    parser.add_argument("--seconds", type=int, required=True)
    parser.add_argument("--parallel", type=int, default=1)
    parser.add_argument("--targets", nargs="+", required=True)
    parser.add_argument("-o", "--output", required=True)
    # The slowest target of the 30-minute benchmark ran 158 a second on a 2-core EPYC and the
    # slowest on an older 2-core machine 38: 10 leaves room for slower machines and still
    # catches a collapse to a few a second.
    parser.add_argument("--min-exec-per-s", type=int, default=10)
    args = parser.parse_args()

    targets = [read_target(t, args.logs, args.findings) for t in args.targets]
    for t in targets:
        t["slow"] = t["executions_per_s"] < args.min_exec_per_s
    report = {
        "seconds_per_target": args.seconds,
        "targets_at_once": args.parallel,
        "fuzzing_seconds": round(sum(t["seconds"] for t in targets), 1),
        "executions": sum(t["executions"] for t in targets),
        "findings": sum(len(t["findings"]) for t in targets),
        "min_executions_per_s": args.min_exec_per_s,
        "slow_targets": [t["target"] for t in targets if t["slow"]],
        "targets": targets,
    }
    tmp = args.output + ".tmp"
    with open(tmp, "w") as f:
        json.dump(report, f, indent=2)
        f.write("\n")
    os.replace(tmp, args.output)

    print(f"{'target':22} {'seconds':>7} {'executions':>12} {'exec/s':>8} {'cov':>6} {'ft':>7} "
          f"{'corpus':>7} {'findings':>8}")
    for t in targets:
        print(f"{t['target']:22} {t['seconds']:7.0f} {t['executions']:12d} {t['executions_per_s']:8d} "
              f"{t['coverage_edges']:6d} {t['coverage_features']:7d} {t['corpus_inputs']:7d} "
              f"{len(t['findings']):8d}{'  slow' if t['slow'] else ''}")
    print(f"{'all':22} {report['fuzzing_seconds']:7.0f} {report['executions']:12d}   "
          f"report: {args.output}")
    for t in targets:
        if t["slow"]:
            print(f"fuzz.sh: {t['target']}: warning: {t['executions_per_s']} inputs a second, "
                  f"below {args.min_exec_per_s} (peak RSS {t['peak_rss_mb']} MB): the run explored "
                  f"almost nothing; look for slow or huge inputs in its corpus (log: {t['log']})",
                  file=sys.stderr)
    failed = [t for t in targets if t["findings"] or t["exit_code"] != 0]
    for t in failed:
        print(f"fuzz.sh: {t['target']}: exit {t['exit_code']}, findings: "
              f"{', '.join(t['findings']) or 'none'} (log: {t['log']})", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
