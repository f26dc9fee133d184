#!/usr/bin/env python3
"""Summarises a scripts/fuzz.sh run: per target, executions, coverage (libFuzzer's "cov",
edges, and "ft", features), corpus size, peak RSS and findings (crash-, leak-, timeout-,
oom- inputs), read from each target's log, exit status and findings folder. Writes JSON,
prints a table, and exits 1 when any target found something or did not finish cleanly."""
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
    args = parser.parse_args()

    targets = [read_target(t, args.logs, args.findings) for t in args.targets]
    report = {
        "seconds_per_target": args.seconds,
        "targets_at_once": args.parallel,
        "fuzzing_seconds": round(sum(t["seconds"] for t in targets), 1),
        "executions": sum(t["executions"] for t in targets),
        "findings": sum(len(t["findings"]) for t in targets),
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
              f"{len(t['findings']):8d}")
    print(f"{'all':22} {report['fuzzing_seconds']:7.0f} {report['executions']:12d}   "
          f"report: {args.output}")
    failed = [t for t in targets if t["findings"] or t["exit_code"] != 0]
    for t in failed:
        print(f"fuzz.sh: {t['target']}: exit {t['exit_code']}, findings: "
              f"{', '.join(t['findings']) or 'none'} (log: {t['log']})", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
