#!/usr/bin/env python3
"""Reading ahead on a flight, and the bytes fetched against the bytes the view needed (issue 49).

For each pyramid, from its folder and over HTTP (Debian's nginx on 127.0.0.1 behind
terrain-test-proxy with a latency before every answer, as remote_arrival_bench.py), runs the
default camera path as a real-time user sees it (no --settle: late tiles are drawn by their
ancestors, never a hole),

  terrain-render PYRAMID_OR_URL --frames N --every 0 --error-px E --json [SETTING]

with an empty disk cache each run, alternating three settings: the default (reading ahead
below waiting leaves and along the camera's motion), --read-ahead-frames 0 (below waiting
leaves only) and --no-prefetch (none). From telemetry.csv: the frames not at full detail
(lod_waiting_splits > 0: drawn leaves too coarse for ε whose children are not in yet), the sum
of lod_waiting_splits over the flight, the reads asked for (requests_made) and the payload
bytes read (stored_bytes_read); over HTTP also fetched_bytes and fetched_per_needed_byte
(whole files come, so a view that needs a few patches of a shard pays for all of it). Writes
OUT/read-ahead-bench.json and .md with the median of the repeats. Rerun with:

  tools/bench/read_ahead_bench.py --build build --out out/bench PYRAMID...
"""
import argparse
import csv
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from remote_arrival_bench import Nginx, Proxy  # noqa: E402

SETTINGS = [("default", []), ("motion off", ["--read-ahead-frames", "0"]),
            ("none", ["--no-prefetch"])]


def flight(render, location, frames, error_px, size, flags):
    """One run's figures."""
    with tempfile.TemporaryDirectory(prefix="read-ahead-") as work:
        env = dict(os.environ, TERRAIN_CACHE_DIR=str(Path(work) / "cache"))
        out = Path(work) / "out"
        command = [render, location, "--frames", str(frames), "--every", "0",
                   "--error-px", str(error_px), "--width", str(size[0]),
                   "--height", str(size[1]), "-o", str(out), "--json"] + flags
        done = subprocess.run(command, env=env, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(command)} failed:\n{done.stderr}")
        summary = json.loads(done.stdout)["telemetry"]
        with open(out / "telemetry.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        waiting = [int(r["lod_waiting_splits"]) for r in rows]
        return {"frames": len(rows),
                "frames_waiting": sum(1 for w in waiting if w > 0),
                "waiting_splits": sum(waiting),
                "requests_made": summary["totals"]["requests_made"],
                "stored_bytes_read": summary["totals"]["stored_bytes_read"],
                "fetched_bytes": summary["http"]["fetched_bytes"],
                "fetched_per_needed_byte": summary["http"]["fetched_per_needed_byte"]}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("pyramids", nargs="+", type=Path)
    parser.add_argument("--build", type=Path, default=Path("build"))
    parser.add_argument("--out", type=Path, default=Path("out/bench"))
    parser.add_argument("--latency-ms", type=int, default=50,
                        help="the HTTP runs' delay before every answer (-1: no HTTP runs)")
    parser.add_argument("--frames", type=int, default=240)
    parser.add_argument("--error-px", type=float, default=2.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--size", default="320x180")
    args = parser.parse_args()
    render = str(args.build / "tools/terrain-render/terrain-render")
    proxy_program = str(args.build / "tests/tools/terrain-test-proxy")
    size = tuple(int(v) for v in args.size.split("x"))
    rows = []
    for pyramid in args.pyramids:
        pyramid = pyramid.resolve()
        server = Nginx(pyramid.parent) if args.latency_ms >= 0 else None
        try:
            networks = [("folder", None)]
            if server:
                networks.append((f"HTTP {args.latency_ms} ms", args.latency_ms))
            for network, latency in networks:
                proxy = None if latency is None else Proxy(proxy_program, server.port, latency, 0)
                location = (str(pyramid) if proxy is None
                            else f"http://127.0.0.1:{proxy.port}/{pyramid.name}")
                runs = {name: [] for name, _ in SETTINGS}
                for _ in range(args.repeats):
                    for name, flags in SETTINGS:
                        runs[name].append(
                            flight(render, location, args.frames, args.error_px, size, flags))
                if proxy:
                    proxy.stop()
                for name, _ in SETTINGS:
                    row = {"pyramid": pyramid.name, "network": network, "reading_ahead": name,
                           "runs": runs[name]}
                    for key in runs[name][0]:
                        values = [r[key] for r in runs[name] if r[key] is not None]
                        row[key] = statistics.median(values) if values else None
                    rows.append(row)
                    print(json.dumps({k: v for k, v in row.items() if k != "runs"}),
                          file=sys.stderr)
        finally:
            if server:
                server.stop()
    args.out.mkdir(parents=True, exist_ok=True)
    report = {"machine": {"cpus": os.cpu_count(), "platform": platform.platform()},
              "error_px": args.error_px, "size": args.size, "frames": args.frames,
              "repeats": args.repeats, "rows": rows}
    (args.out / "read-ahead-bench.json").write_text(json.dumps(report, indent=1) + "\n")
    lines = ["| pyramid | network | reading ahead | frames not at full detail | waiting splits "
             "| reads | payload MB read | MB fetched | fetched per byte needed |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ratio = r["fetched_per_needed_byte"]
        lines.append(
            f"| {r['pyramid']} | {r['network']} | {r['reading_ahead']} | "
            f"{r['frames_waiting']:g} of {r['frames']:g} | {r['waiting_splits']:g} | "
            f"{r['requests_made']:g} | {r['stored_bytes_read'] / 1e6:.2f} | "
            f"{r['fetched_bytes'] / 1e6:.2f} | {'–' if ratio is None else f'{ratio:.2f}'} |")
    (args.out / "read-ahead-bench.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
