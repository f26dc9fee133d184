#!/usr/bin/python3
"""Tests of the chart tool and of terrain-bench's output (run by CTest, tests/tools).

  check_charts.py --script terrain_charts.py --work DIR
      writes a small summary CSV with two methods, a per-frame CSV and a telemetry CSV,
      runs the chart tool on them and checks every PNG (signature, decodes, not blank) and
      report.md; then checks that a CSV without a needed column fails with a message.
  check_charts.py --check-bench DIR
      checks a terrain-bench --report folder: the CSVs' columns and rows, bench.json, the
      PNGs and report.md; for a globe pyramid also the per-frame figures the globe adds (the
      LOD's own error, the camera's height; no crack against the globe reference image), the
      charts by height and the report's globe section.
Exit status 0 when every check passes; the first failure is printed.
"""

import argparse
import csv
import json
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
GLOBE_CHARTS = ["globe_error_vs_height.png", "globe_psnr_vs_height.png",
                "globe_triangles_vs_height.png"]
CHARTS = ["triangles_vs_error.png", "frame_time_vs_error.png", "psnr_vs_triangles.png",
          "error_timeline.png", "telemetry_timeline.png"]


def fail(message):
    print(f"check_charts.py: {message}", file=sys.stderr)
    sys.exit(1)


def check_png(path):
    if not os.path.isfile(path):
        fail(f"{path}: missing")
    with open(path, "rb") as f:
        if f.read(8) != PNG_SIGNATURE:
            fail(f"{path}: not a PNG")
    image = matplotlib.image.imread(path)
    if image.ndim != 3 or image.shape[0] < 200 or image.shape[1] < 300:
        fail(f"{path}: unexpected image shape {image.shape}")
    if float(image[..., :3].std()) < 0.01:
        fail(f"{path}: blank image")


def write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows(rows)


SUMMARY_HEADER = ["method", "threshold_px", "frames", "triangles_mean", "triangles_max",
                  "patches_mean", "draw_calls_max", "lod_update_us_mean", "lod_update_us_p95",
                  "gpu_ms_mean", "gpu_ms_source", "draw_ms_mean", "frame_ms_mean", "frame_ms_p95",
                  "resident_bytes_max", "error_max_px", "error_max_median_px", "error_mean_px",
                  "error_p99_mean_px", "frames_over_threshold", "error_fixed_diagonal_max_px",
                  "error_max_raw_px", "depth_outlier_pixels_total", "rmse_mean", "psnr_db_mean",
                  "psnr_db_min", "crack_pixels_total", "popping_levels_mean", "frames_waited"]


def summary_row(method, eps, triangles, error, psnr, frame_ms):
    values = {"method": method, "threshold_px": eps, "frames": 10, "triangles_mean": triangles,
              "triangles_max": triangles * 1.2, "patches_mean": triangles / 500.0,
              "draw_calls_max": 1, "lod_update_us_mean": 120, "lod_update_us_p95": 200,
              "gpu_ms_mean": frame_ms / 2, "gpu_ms_source": "llvmpipe-cpu", "draw_ms_mean": frame_ms,
              "frame_ms_mean": frame_ms, "frame_ms_p95": frame_ms * 1.5, "resident_bytes_max": 4 << 20,
              "error_max_px": error, "error_max_median_px": error * 0.8, "error_mean_px": error / 10,
              "error_p99_mean_px": error / 2, "frames_over_threshold": 1,
              "error_fixed_diagonal_max_px": error * 2, "error_max_raw_px": error,
              "depth_outlier_pixels_total": 0, "rmse_mean": 30 - psnr / 2, "psnr_db_mean": psnr,
              "psnr_db_min": psnr - 2, "crack_pixels_total": 0, "popping_levels_mean": 0.5,
              "frames_waited": 0}
    return [values[k] for k in SUMMARY_HEADER]


def run_chart_tool(script, args):
    return subprocess.run([sys.executable, script] + args, capture_output=True, text=True)


def test_small_csv(script, work):
    os.makedirs(work, exist_ok=True)
    summary = os.path.join(work, "summary.csv")
    rows = []
    for method, scale in (("yusov2011", 1.0), ("uniform-grid", 3.0)):
        for eps, tri, err, psnr, ms in ((1, 100000, 1.1, 32, 30), (2, 40000, 2.2, 30, 12),
                                        (4, 9000, 4.3, 28, 4), (8, 2000, 8.1, 27, 2)):
            rows.append(summary_row(method, eps, tri * scale, err, psnr - scale, ms * scale))
    write_csv(summary, SUMMARY_HEADER, rows)
    frames = os.path.join(work, "frames.csv")
    frame_rows = []
    for eps in (1, 2, 4, 8):
        for frame in range(10):
            frame_rows.append(["yusov2011", eps, frame, 0.9 * eps + 0.05 * frame])
    write_csv(frames, ["method", "threshold_px", "frame", "error_max_px"], frame_rows)
    telemetry = os.path.join(work, "telemetry.csv")
    telemetry_rows = []
    for frame in range(30):
        telemetry_rows.append([frame, 0.033 * frame, 10 + frame % 5, min(frame * 3, 60), frame * 3,
                               max(0, 10 - frame), 2 if frame < 10 else 0,
                               "" if frame == 0 else 5 + frame % 3, "" if frame == 0 else 9,
                               "" if frame == 0 else 12])
    write_csv(telemetry, ["frame", "time_s", "frame_ms", "gpu_layers_used", "cpu_cache_entries",
                          "queue_depth", "io_in_flight", "load_latency_p50_ms",
                          "load_latency_p95_ms", "load_latency_p99_ms"], telemetry_rows)
    out = os.path.join(work, "charts")
    result = run_chart_tool(script, ["--summary", summary, "--frames", frames, "--telemetry", telemetry,
                                     "--out", out, "--report"])
    if result.returncode != 0:
        fail(f"the chart tool failed ({result.returncode}): {result.stderr}")
    for name in CHARTS:
        check_png(os.path.join(out, name))
    with open(os.path.join(out, "report.md")) as f:
        report = f.read()
    for needle in ("| yusov2011 | 1 |", "| uniform-grid | 8 |", "triangles_vs_error.png"):
        if needle not in report:
            fail(f"report.md lacks '{needle}'")
    # The yardstick ratio at equal measured error: rtin's 1,000 triangles at 0.9 px against
    # yusov2011's 10,000 at 0.8 px and 4,000 at 1.6 px, interpolated log-log: 8,563, 8.56×.
    yard = os.path.join(work, "yardstick-frames.csv")
    write_csv(yard, ["method", "threshold_px", "frame", "error_max_px", "triangles"],
              [[m, eps, f, err, tri] for f in range(3)
               for m, eps, err, tri in (("rtin", 1, 0.9, 1000), ("yusov2011", 1, 0.8, 10000),
                                        ("yusov2011", 2, 1.6, 4000))])
    out = os.path.join(work, "yardstick")
    result = run_chart_tool(script, ["--summary", summary, "--frames", yard, "--out", out, "--report"])
    if result.returncode != 0:
        fail(f"the chart tool failed on the yardstick frames ({result.returncode}): {result.stderr}")
    check_png(os.path.join(out, "yardstick_ratio.png"))
    with open(os.path.join(out, "report.md")) as f:
        if "| yusov2011 | 8.56× (max 8.56×, 3 frames) |" not in f.read():
            fail("report.md: the yardstick ratio at equal measured error is not 8.56× on 3 frames")
    # A CSV without a needed column: a clear message and a non-zero exit status.
    broken = os.path.join(work, "broken.csv")
    write_csv(broken, ["method", "threshold_px", "triangles_mean"], [["yusov2011", 1, 5]])
    result = run_chart_tool(script, ["--summary", broken, "--out", os.path.join(work, "broken")])
    if result.returncode == 0 or "error_max_px" not in result.stderr:
        fail(f"a summary without error_max_px must fail naming it (exit {result.returncode}, "
             f"stderr {result.stderr!r})")


def check_report(folder, charts, command, table_marker):
    """Every chart a valid PNG; report.md holds the command that made it and its table."""
    for name in charts:
        check_png(os.path.join(folder, name))
    with open(os.path.join(folder, "report.md")) as f:
        report = f.read()
    if command not in report or table_marker not in report:
        fail("report.md lacks the command or the table")


def check_bench(folder):
    with open(os.path.join(folder, "bench.json")) as f:
        bench = json.load(f)
    thresholds = [t["threshold_px"] for t in bench["thresholds"]]
    if not thresholds:
        fail("bench.json has no thresholds")
    with open(os.path.join(folder, "summary.csv"), newline="") as f:
        summary = list(csv.DictReader(f))
    if [float(r["threshold_px"]) for r in summary] != thresholds:
        fail("summary.csv and bench.json disagree on the thresholds")
    with open(os.path.join(folder, "frames.csv"), newline="") as f:
        frames = list(csv.DictReader(f))
    if len(frames) != bench["frames"] * len(thresholds):
        fail(f"frames.csv has {len(frames)} rows, expected {bench['frames']} × {len(thresholds)}")
    for row in frames:
        for key in ("triangles", "error_max_px", "psnr_db", "crack_pixels", "resident_bytes",
                    "gpu_ms_source", "lod_update_us", "non_finite_pixels"):
            if row.get(key, "") == "":
                fail(f"frames.csv: empty {key} in frame {row.get('frame')}")
        if int(row["non_finite_pixels"]) != 0:
            fail(f"frames.csv: frame {row['frame']}: {row['non_finite_pixels']} pixels whose "
                 "error could not be measured on ordinary terrain")
        if int(row["triangles"]) <= 0 or int(row["draw_calls"]) != 1:
            fail(f"frames.csv: frame {row['frame']}: {row['triangles']} triangles, "
                 f"{row['draw_calls']} draw calls")
    globe = bench.get("tiling") == "globe"
    if globe:
        for row in frames:
            for key in ("lod_error_max_px", "camera_height_m", "horizon_culled"):
                if row.get(key, "") == "":
                    fail(f"frames.csv: empty {key} in {row['method']} frame {row['frame']}")
            if int(row["crack_pixels"]) != 0:
                fail(f"{row['method']} ε = {row['threshold_px']}, frame {row['frame']}: "
                     f"{row['crack_pixels']} crack pixels against the globe reference image")
            for key in ("boundary_artefact_pixels", "boundary_silhouette_pixels",
                        "shading_seam_levels"):
                if row.get(key, "") == "":
                    fail(f"frames.csv: no {key} in {row['method']} frame {row['frame']}")
        if not any(t["method"].endswith("-no-horizon-culling") for t in bench["thresholds"]):
            fail("bench.json: no run without horizon culling to compare with")
        for t in bench["thresholds"]:
            if "full_detail_after_arrival" not in t:
                fail(f"bench.json: {t['method']} ε = {t['threshold_px']}: no arrival figure")
        for key in ("same_view_straight_down_10km", "storage", "sources"):
            if not (bench.get("globe") or {}).get(key):
                fail(f"bench.json: no globe.{key}")
        # One per source over a coarser one: none for a pyramid of one source.
        if not isinstance((bench.get("globe") or {}).get("seams"), list):
            fail("bench.json: no globe.seams")
    check_report(folder, CHARTS + (GLOBE_CHARTS if globe else []), bench["command"],
                 "## The globe" if globe else "| yusov2011 |")
    # One curve, one table row set and one failure line per method flown.
    methods = bench.get("methods", [])
    if not methods or sorted(set(r["method"] for r in summary)) != sorted(methods):
        fail(f"summary.csv's methods {sorted(set(r['method'] for r in summary))} are not "
             f"bench.json's {methods}")
    if len(methods) > 1:
        with open(os.path.join(folder, "report.md")) as f:
            report = f.read()
        failures = report.partition("## Where each method fails")[2]
        if not failures:
            fail("report.md has no \"Where each method fails\" section")
        for method in methods:
            if f"**{method}**" not in failures:
                fail(f"report.md: no line for {method} under \"Where each method fails\"")
            if f"| {method} |" not in report:
                fail(f"report.md: no table row for {method}")
    # With the yardstick flown: the frame-by-frame ratio at equal measured error.
    if "rtin" in methods:
        if not os.path.exists(os.path.join(folder, "yardstick_ratio.png")):
            fail("no yardstick_ratio.png although rtin was flown")
        with open(os.path.join(folder, "report.md")) as f:
            if "yardstick at equal measured error" not in f.read():
                fail("report.md has no table of triangles against the yardstick at equal error")
    # --stability: every method and threshold at every stress pose, and a failure line per
    # method in the report.
    stability = bench.get("stability")
    if stability:
        poses = [p["name"] for p in stability.get("poses", [])]
        for expected in ("whole-terrain", "cliff", "peak", "grazing"):
            if expected not in poses:
                fail(f"bench.json: no {expected} among the stress poses {poses}")
        with open(os.path.join(folder, "stability.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        if len(rows) != len(poses) * len(summary):
            fail(f"stability.csv has {len(rows)} rows, expected {len(poses)} poses × "
                 f"{len(summary)} runs")
        for row in rows:
            if row["pose"] not in poses or row.get("error_max_px", "") == "":
                fail(f"stability.csv: a row without its pose or error: {row.get('pose')}")
        with open(os.path.join(folder, "report.md")) as f:
            section = f.read().partition("## Where each method fails at the stress poses")[2]
        if not section:
            fail("report.md has no \"Where each method fails at the stress poses\" section")
        for method in methods:
            if f"**{method}**" not in section.partition("## ")[0]:
                fail(f"report.md: no stress-pose line for {method}")
        for pose in poses:
            if f"**{pose}**" not in section:
                fail(f"report.md: the stress pose {pose} is not described")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--script")
    parser.add_argument("--work")
    parser.add_argument("--check-bench")
    args = parser.parse_args()
    if args.check_bench:
        check_bench(args.check_bench)
    else:
        if not args.script or not args.work:
            fail("give --script and --work, or --check-bench")
        test_small_csv(args.script, args.work)
    print("check_charts.py: all checks passed")


if __name__ == "__main__":
    main()
