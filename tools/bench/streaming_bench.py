#!/usr/bin/env python3
"""Streaming benchmark: I/O thread throughput and request → resident latency.

For every real DEM in ../shared/data (the list of pyramid_build_bench.py), builds the
pyramid with default patches (129² + apron) and runs
  terrain-io-bench PYRAMID --seconds 5 --json
      tiles per second one I/O thread reads and decodes from the page cache
  terrain-stress PYRAMID --flight cruise --width 1920 --height 1080 --error-px 2
                 --cpu-cache-mib 256 --gpu-layers 512 --duration-s 30 --json
      a steady 1080p flight at "normal speed" (max(200 m/s, 5 sample spacings per
      second), max(300 m, 10 spacings) above the ground): load latency over the run and
      after a 5 s warm-up, in ms and in frames
and writes OUT_DIR/streaming-bench.json and .md. Rerun with:
  /usr/bin/python3 tools/bench/streaming_bench.py --build build --out out/bench
(--max-error-m 1 builds the pyramids lossy, docs/pyramid-format.md "Lossy storage"). On llvmpipe a 1080p frame takes tens of milliseconds, so the latency in frames is the
figure that carries over to a GPU; the ms figures are this machine's.
"""
import argparse
import json
import platform
import shutil
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from pyramid_build_bench import REAL_DEMS  # noqa: E402  (same folder)

REPO = Path(__file__).resolve().parents[2]


def run_json(command):
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"failed ({result.returncode}): {' '.join(map(str, command))}\n{result.stderr}")
    return json.loads(result.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=str(REPO / "build"), help="build folder")
    parser.add_argument("--out", default=str(REPO / "out" / "bench"), help="results folder")
    parser.add_argument("--shared", default=str(REPO.parent / "shared" / "data"), help="real DEMs")
    parser.add_argument("--scratch", default="/tmp/terrain-bench", help="pyramids")
    parser.add_argument("--flight-seconds", type=float, default=30.0)
    parser.add_argument("--max-error-m", type=float, default=0.0,
                        help="terrain-build --max-error-m: lossy pyramids (0: lossless)")
    args = parser.parse_args()

    tools = Path(args.build) / "tools"
    out, scratch = Path(args.out), Path(args.scratch)
    out.mkdir(parents=True, exist_ok=True)
    scratch.mkdir(parents=True, exist_ok=True)
    rows = []
    for name, flags in REAL_DEMS:
        dem = Path(args.shared) / name
        pyramid = scratch / (Path(name).stem + ".stream.pyramid")
        print(f"{name}: building {pyramid} ...", flush=True)
        shutil.rmtree(pyramid, ignore_errors=True)
        built = run_json([tools / "terrain-build" / "terrain-build", dem, *flags, "-o", pyramid,
                          "--max-error-m", args.max_error_m, "--json", "--quiet"])
        manifest = json.loads((pyramid / "manifest.json").read_text())
        io = run_json([tools / "terrain-io-bench" / "terrain-io-bench", pyramid, "--seconds", "5", "--json"])
        georef = manifest["georeference"]
        spacing = georef["pixelSizeX"] if georef["crsKind"] == "projected" else 30.0
        if georef["crsKind"] == "geographic":
            spacing = georef["pixelSizeX"] * 111_320.0  # metres per degree at the equator
        speed = max(200.0, 5.0 * spacing)
        altitude = max(300.0, 10.0 * spacing)
        print(f"{name}: cruise at {speed:.0f} m/s, {altitude:.0f} m ...", flush=True)
        flight = run_json([tools / "terrain-stress" / "terrain-stress", pyramid, "--flight", "cruise",
                           "--speed-mps", speed, "--altitude-m", altitude, "--width", "1920",
                           "--height", "1080", "--error-px", "2", "--cpu-cache-mib", "256",
                           "--gpu-layers", "512", "--duration-s", args.flight_seconds, "--json"])
        rows.append({
            "dem": name,
            "patches": built.get("patches"),
            "pyramid_mib": built.get("bytes", 0) / 2**20,
            "max_error_m": args.max_error_m,
            "io_tiles_per_s": io["tiles_per_s"],
            "io_mib_per_s": io["mib_per_s"],
            "cruise_speed_mps": speed,
            "cruise_altitude_m": altitude,
            "frames": flight["frames"],
            "frame_ms_p50": flight["telemetry"]["frame_ms"]["p50"],
            "loads": flight["load_latency_ms"]["count"],
            "latency_ms_p50": flight["load_latency_ms"]["p50"],
            "latency_ms_p99": flight["load_latency_ms"]["p99"],
            "warm_loads": flight["after_warmup"]["load_latency_ms"]["count"],
            "warm_latency_ms_p99": flight["after_warmup"]["load_latency_ms"]["p99"],
            "warm_latency_frames_p99": flight["after_warmup"]["load_latency_frames"]["p99"],
            "violations": flight["invariant_violations"],
            "gl_renderer": flight["gl"].get("renderer"),
        })
    summary = {"machine": platform.node(), "cpus": len(__import__("os").sched_getaffinity(0)), "rows": rows}
    (out / "streaming-bench.json").write_text(json.dumps(summary, indent=2) + "\n")
    fmt = lambda v, f="{:.0f}": "–" if v is None else f.format(v)  # noqa: E731
    lines = ["| DEM | patches | I/O tiles/s (1 thread) | MiB/s | frame ms p50 | loads | latency p50 / p99 ms (all) | after warm-up: loads, p99 ms, p99 frames | violations |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['dem']} | {r['patches']} | {fmt(r['io_tiles_per_s'])} | {fmt(r['io_mib_per_s'], '{:.1f}')} | "
                     f"{fmt(r['frame_ms_p50'], '{:.1f}')} | {r['loads']} | {fmt(r['latency_ms_p50'])} / {fmt(r['latency_ms_p99'])} | "
                     f"{r['warm_loads']}, {fmt(r['warm_latency_ms_p99'])}, {fmt(r['warm_latency_frames_p99'], '{:.1f}')} | {r['violations']} |")
    renderer = rows[0]["gl_renderer"] if rows else "?"
    text = (f"# Streaming benchmark\n\nRenderer: {renderer}. Command: "
            f"`/usr/bin/python3 tools/bench/streaming_bench.py --build {args.build} --out {args.out}`\n\n"
            + "\n".join(lines) + "\n")
    (out / "streaming-bench.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
