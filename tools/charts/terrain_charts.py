#!/usr/bin/python3
"""Speed-against-accuracy charts (and a Markdown report) from terrain-bench's CSV files.

Charts, as PNG, one curve per LOD method (the `method` column; several summary files may
be given, so comparison methods drop in as more curves):
  triangles_vs_error.png   mean triangles per frame against the measured screen-space error
  frame_time_vs_error.png  frame time (and the draw's GL_TIME_ELAPSED) against the error
  psnr_vs_triangles.png    PSNR of the shaded image against triangles
  error_timeline.png       each frame's largest measured error along the flight (frames.csv)
  telemetry_timeline.png   frame time, resident tiles, queue depth and load latency over a
                           flight, from any telemetry CSV (docs/telemetry.md)
A globe pyramid's bench (bench.json's "tiling": "globe", docs/globe.md) adds charts by height,
one curve per ε, along the flight from orbit to the ground (frames.csv):
  globe_error_vs_height.png     each frame's largest error against the sources and against
                                the pyramid's finest level (the LOD's own), by height
  globe_psnr_vs_height.png      PSNR against the globe reference image, by height
  globe_triangles_vs_height.png triangles per frame, by height

Usage:
  terrain_charts.py --bench-dir DIR --out DIR [--report]
  terrain_charts.py --summary S.csv [--summary T.csv ...] [--frames F.csv]
                    [--telemetry TELEMETRY.csv] --out DIR
  terrain_charts.py --telemetry TELEMETRY.csv --out DIR   (the timeline of any flight)
  terrain_charts.py --check                               (matplotlib loads?)
Run it with Debian's /usr/bin/python3, which sees python3-matplotlib. Definitions of every
figure: docs/accuracy.md.
"""

import argparse
import csv
import json
import math
import os
import sys


def fail(message):
    print(f"terrain_charts.py: {message}", file=sys.stderr)
    sys.exit(2)


try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as error:  # pragma: no cover - depends on the machine
    fail(f"matplotlib is missing ({error}): install Debian's python3-matplotlib and run this "
         "script with /usr/bin/python3 (a pyenv or venv python3 does not see it)")


def read_csv(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as error:
        fail(f"{path}: cannot read: {error.strerror}")
    if not rows:
        fail(f"{path}: no data rows")
    return rows


def number(row, key, path="CSV"):
    if key not in row:
        fail(f"{path}: no column '{key}'")
    text = row[key]
    if text is None or text == "":
        return math.nan
    try:
        return float(text)
    except ValueError:
        fail(f"{path}: column '{key}' holds '{text}', not a number")


def optional_number(row, key, path="CSV"):
    """A column older files lack (NaN there, as an empty field)."""
    return number(row, key, path) if key in row else math.nan


def boundary_artefacts_cell(row, path):
    """The boundary artefacts, and in brackets the edge pixels at silhouettes that the
    detector cannot judge (newer files)."""
    artefacts = fmt(optional_number(row, "boundary_artefact_pixels_total", path), 0)
    silhouettes = optional_number(row, "boundary_silhouette_pixels_total", path)
    return artefacts if not math.isfinite(silhouettes) else f"{artefacts} ({fmt(silhouettes, 0)})"


def by_method(rows):
    methods = {}
    for row in rows:
        methods.setdefault(row.get("method", "yusov2011"), []).append(row)
    for method_rows in methods.values():
        method_rows.sort(key=lambda r: float(r["threshold_px"]))
    return methods


def finite(xs, ys):
    pairs = [(x, y) for x, y in zip(xs, ys) if math.isfinite(x) and math.isfinite(y)]
    return [p[0] for p in pairs], [p[1] for p in pairs]


def positive_log(ax, axis, values):
    if values and all(v > 0 for v in values if math.isfinite(v)):
        (ax.set_xscale if axis == "x" else ax.set_yscale)("log")


def annotate_thresholds(ax, xs, ys, thresholds):
    for x, y, t in zip(xs, ys, thresholds):
        if math.isfinite(x) and math.isfinite(y):
            ax.annotate(f"ε={t:g}", (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)


def save(fig, out_dir, name):
    path = os.path.join(out_dir, name)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def chart_triangles_vs_error(methods, out_dir, source):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    all_x, all_y = [], []
    for method, rows in methods.items():
        t = [number(r, "threshold_px", source) for r in rows]
        tri = [number(r, "triangles_mean", source) for r in rows]
        emax = [number(r, "error_max_px", source) for r in rows]
        emean = [number(r, "error_mean_px", source) for r in rows]
        x, y = finite(emax, tri)
        line, = ax.plot(x, y, "o-", label=f"{method}: largest error")
        xm, ym = finite(emean, tri)
        ax.plot(xm, ym, "o--", mfc="none", color=line.get_color(), label=f"{method}: mean error")
        annotate_thresholds(ax, emax, tri, t)
        all_x += x + xm
        all_y += y + ym
    positive_log(ax, "x", all_x)
    positive_log(ax, "y", all_y)
    ax.set_xlabel("measured screen-space error (px)")
    ax.set_ylabel("triangles per frame (mean)")
    ax.set_title("Triangles against measured error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, out_dir, "triangles_vs_error.png")


def chart_frame_time_vs_error(methods, out_dir, source):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    all_x = []
    for method, rows in methods.items():
        t = [number(r, "threshold_px", source) for r in rows]
        emax = [number(r, "error_max_px", source) for r in rows]
        frame = [number(r, "frame_ms_mean", source) for r in rows]
        gpu = [number(r, "gpu_ms_mean", source) for r in rows]
        gpu_source = rows[0].get("gpu_ms_source", "")
        x, y = finite(emax, frame)
        line, = ax.plot(x, y, "o-", label=f"{method}: frame time (wall)")
        xg, yg = finite(emax, gpu)
        gpu_label = "draw time, llvmpipe CPU" if gpu_source == "llvmpipe-cpu" else "GPU time"
        ax.plot(xg, yg, "s--", mfc="none", color=line.get_color(),
                label=f"{method}: {gpu_label} (GL_TIME_ELAPSED)")
        annotate_thresholds(ax, emax, frame, t)
        all_x += x
    positive_log(ax, "x", all_x)
    ax.set_xlabel("measured screen-space error, largest (px)")
    ax.set_ylabel("milliseconds per frame (mean)")
    ax.set_title("Frame time against measured error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, out_dir, "frame_time_vs_error.png")


def chart_psnr_vs_triangles(methods, out_dir, source):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    all_x = []
    for method, rows in methods.items():
        t = [number(r, "threshold_px", source) for r in rows]
        tri = [number(r, "triangles_mean", source) for r in rows]
        psnr = [number(r, "psnr_db_mean", source) for r in rows]
        x, y = finite(tri, psnr)
        ax.plot(x, y, "o-", label=method)
        annotate_thresholds(ax, tri, psnr, t)
        all_x += x
    positive_log(ax, "x", all_x)
    ax.set_xlabel("triangles per frame (mean)")
    ax.set_ylabel("PSNR of the shaded image (dB, mean)")
    ax.set_title("Image quality against triangles")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return save(fig, out_dir, "psnr_vs_triangles.png")


def chart_error_timeline(frame_rows, out_dir, source):
    fig, ax = plt.subplots(figsize=(7.2, 4.2))
    series = {}
    for row in frame_rows:
        key = (row.get("method", "yusov2011"), number(row, "threshold_px", source))
        series.setdefault(key, []).append(row)
    for (method, threshold), rows in sorted(series.items(), key=lambda kv: (kv[0][0], kv[0][1])):
        frames = [number(r, "frame", source) for r in rows]
        emax = [number(r, "error_max_px", source) for r in rows]
        line, = ax.plot(frames, emax, "-", lw=1.2, label=f"{method} ε={threshold:g}")
        ax.axhline(threshold, color=line.get_color(), lw=0.7, ls=":")
    ax.set_yscale("log")
    ax.set_xlabel("frame")
    ax.set_ylabel("largest measured error (px); dotted: ε")
    ax.set_title("Measured error along the flight")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    return save(fig, out_dir, "error_timeline.png")


def triangles_at_error(points, error):
    """Triangles a method needs for `error` px, from its (measured error, triangles) points of
    one frame: log-log interpolation between the two points that bracket it; None when the
    method does not reach `error` or never goes above it on that frame."""
    points = sorted((e, t) for e, t in points if e > 0 and t > 0 and math.isfinite(e))
    for (e0, t0), (e1, t1) in zip(points, points[1:]):
        if e0 <= error <= e1:
            if e1 == e0:
                return min(t0, t1)
            a = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0)))
    exact = [t for e, t in points if e == error]
    return min(exact) if exact else None


def yardstick_ratios(frame_rows, source):
    """Per frame and yardstick threshold: each method's triangles divided by the yardstick's
    at the yardstick's measured error on that frame (the method's own thresholds
    interpolated, triangles_at_error). {method: {ε: [(frame, ratio)]}}."""
    if not any(r.get("method") == YARDSTICK for r in frame_rows):
        return {}
    by = {}
    for r in frame_rows:
        if r.get("pose"):
            continue
        by.setdefault(r.get("method", "yusov2011"), {}).setdefault(
            int(number(r, "frame", source)), []).append(
            (number(r, "threshold_px", source), number(r, "error_max_px", source),
             number(r, "triangles", source)))
    stick = by.get(YARDSTICK)
    if not stick:
        return {}
    out = {}
    for method, frames in by.items():
        if method == YARDSTICK:
            continue
        for frame, yard in stick.items():
            points = [(e, t) for _, e, t in frames.get(frame, [])]
            for eps, error, triangles in yard:
                need = triangles_at_error(points, error)
                if need is not None and triangles > 0:
                    out.setdefault(method, {}).setdefault(eps, []).append((frame, need / triangles))
    return out


def chart_yardstick_ratio(ratios, out_dir):
    fig, ax = plt.subplots(figsize=(7.2, 4.2))
    styles = ["-", "--", ":", "-."]
    colors = {}
    for method, by_eps in ratios.items():
        for i, (eps, series) in enumerate(sorted(by_eps.items())):
            # Frames where the method does not reach the error are gaps, not joined.
            ratio_of = dict(series)
            frames = list(range(min(ratio_of), max(ratio_of) + 1))
            values = [ratio_of.get(f, math.nan) for f in frames]
            kwargs = {"color": colors[method]} if method in colors else {}
            line, = ax.plot(frames, values, styles[i % len(styles)], marker=".", ms=3,
                            lw=1.2, label=f"{method}, {YARDSTICK} at ε={eps:g}", **kwargs)
            colors.setdefault(method, line.get_color())
    ax.set_yscale("log")
    ax.axhline(1.0, color="black", lw=0.7)
    ax.axhline(2.0, color="grey", lw=0.7, ls=":")
    ax.set_xlabel("frame")
    ax.set_ylabel(f"triangles ÷ {YARDSTICK}'s at its measured error")
    ax.set_title(f"Triangles against the {YARDSTICK} yardstick, frame by frame")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    return save(fig, out_dir, "yardstick_ratio.png")


def yardstick_ratio_table(ratios):
    if not ratios:
        return []
    eps_all = sorted({eps for by_eps in ratios.values() for eps in by_eps})
    lines = [f"### Triangles against the {YARDSTICK} yardstick at equal measured error", "",
             f"Frame by frame: the {YARDSTICK}'s largest measured error at each of its thresholds, "
             "and the triangles each method needs for that same measured error on the same frame "
             "(its own thresholds interpolated, log-log); median and largest ratio over the "
             "frames, and on how many frames the method reaches that error at all.", "",
             "| method | " + " | ".join(f"{YARDSTICK} ε = {e:g}" for e in eps_all) + " |",
             "|---|" + "---|" * len(eps_all)]
    for method, by_eps in ratios.items():
        cells = []
        for eps in eps_all:
            values = sorted(r for _, r in by_eps.get(eps, []))
            if not values:
                cells.append("–")
                continue
            median = values[len(values) // 2] if len(values) % 2 else 0.5 * (
                values[len(values) // 2 - 1] + values[len(values) // 2])
            cells.append(f"{fmt(median)}× (max {fmt(values[-1])}×, {len(values)} frames)")
        lines.append(f"| {method} | " + " | ".join(cells) + " |")
    lines.append("")
    return lines


def chart_telemetry_timeline(rows, out_dir, source):
    time = [number(r, "time_s", source) for r in rows]
    fig, axes = plt.subplots(4, 1, figsize=(7.2, 8.0), sharex=True)
    axes[0].plot(time, [number(r, "frame_ms", source) for r in rows], lw=1)
    axes[0].set_ylabel("frame ms")
    axes[1].plot(time, [number(r, "gpu_layers_used", source) for r in rows], lw=1, label="GPU layers used")
    axes[1].plot(time, [number(r, "cpu_cache_entries", source) for r in rows], lw=1, label="CPU cache entries")
    axes[1].set_ylabel("resident tiles")
    axes[1].legend(fontsize=7)
    axes[2].plot(time, [number(r, "queue_depth", source) for r in rows], lw=1, label="queue depth")
    axes[2].plot(time, [number(r, "io_in_flight", source) for r in rows], lw=1, label="reads in flight")
    axes[2].set_ylabel("requests")
    axes[2].legend(fontsize=7)
    for key, label in (("load_latency_p50_ms", "p50"), ("load_latency_p95_ms", "p95"),
                       ("load_latency_p99_ms", "p99")):
        axes[3].plot(time, [number(r, key, source) for r in rows], lw=1, label=label)
    axes[3].set_ylabel("load latency ms")
    axes[3].legend(fontsize=7)
    axes[3].set_xlabel("time (s)")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    axes[0].set_title("Streaming telemetry over the flight")
    return save(fig, out_dir, "telemetry_timeline.png")


def fmt(value, digits=2):
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    if isinstance(value, float) and value.is_integer() and abs(value) >= 1000:
        return f"{value:,.0f}"
    if abs(value) >= 1000:
        return f"{value:,.0f}"
    return f"{value:.{digits}f}"


YARDSTICK = "rtin"
# A shading seam (BoundaryShading.h) above this many 8-bit luma levels is listed as a failure:
# the uniform full-resolution grid, one level everywhere, measures 0.1-0.2 on the shared DEMs.
SHADING_SEAM_VISIBLE_LEVELS = 1.0
# What terrain-bench appends to a method's name for a variant of its draw or LOD.
VARIANTS = ("-coarse-only", "-blocks-only", "-vertex-normals", "-no-horizon-culling")


def base_method(method):
    """The LOD method a run's name is a variant of ("yusov2011-coarse-only": "yusov2011")."""
    for variant in VARIANTS:
        method = method.replace(variant, "")
    return method


def method_sections(bench, summary_rows, summary_path, tol):
    """The methods compared, their triangles against the RTIN yardstick's, and in plain words
    where each one fails: error over ε (for the methods that promise a bound), cracks,
    unmeasurable pixels, and the most popping."""
    methods = by_method(summary_rows)
    if len(methods) < 2:
        return []
    info = (bench or {}).get("method_info", {})
    lines = ["## Methods", ""]
    for method in methods:
        described = info.get(base_method(method), {})
        promise = ("bounds the measured error by ε" if described.get("bounds_error")
                   else "promises no error bound" if described else "")
        lines.append(f"- **{method}**: {described.get('summary', 'no description')}"
                     + (f"; {promise}." if promise else "."))
    lines.append("")
    yardstick = {number(r, "threshold_px", summary_path): number(r, "triangles_mean", summary_path)
                 for r in methods.get(YARDSTICK, [])}
    if yardstick:
        lines += [f"### Triangles against the {YARDSTICK} yardstick", "",
                  f"Mean triangles a frame divided by {YARDSTICK}'s at the same ε (the fewest a "
                  "conforming mesh of the full-resolution samples needs for the same bound). For a "
                  "method that does not bound its error the same ε is not the same accuracy: the "
                  "chart of triangles against measured error compares those.", "",
                  "| method | " + " | ".join(f"ε = {t:g}" for t in sorted(yardstick)) + " |",
                  "|---|" + "---|" * len(yardstick)]
        for method, rows in methods.items():
            by_eps = {number(r, "threshold_px", summary_path): number(r, "triangles_mean", summary_path)
                      for r in rows}
            cells = [fmt(by_eps[t] / yardstick[t], 2) + "×" if t in by_eps and yardstick[t] > 0
                     else "–" for t in sorted(yardstick)]
            lines.append(f"| {method} | " + " | ".join(cells) + " |")
        lines.append("")
    lines += ["## Where each method fails", ""]
    for method, rows in methods.items():
        described = info.get(base_method(method), {})
        bounds = described.get("bounds_error", True)
        failures = []
        for r in rows:
            n = lambda key: number(r, key, summary_path)
            eps = n("threshold_px")
            over = int(n("frames_over_threshold"))
            if over > 0:
                what = (f"over ε + {tol:g} px in {over} of {int(n('frames'))} frames at ε = {eps:g} "
                        f"(largest {fmt(n('error_max_px'))} px)")
                failures.append(what if bounds else what + " — it promises no bound")
            if n("crack_pixels_total") > 0:
                failures.append(f"{int(n('crack_pixels_total'))} crack pixels at ε = {eps:g}")
            overdrawn = optional_number(r, "overdrawn_pixels_total", summary_path)
            if overdrawn > 0:
                failures.append(f"{int(overdrawn)} pixels of terrain where the reference shows "
                                f"none within ε at ε = {eps:g} (a wall, a skirt seen from "
                                "beneath, terrain beyond the data)")
            artefacts = optional_number(r, "boundary_artefact_pixels_total", summary_path)
            if artefacts > 0:
                failures.append(f"{int(artefacts)} boundary-artefact pixels at ε = {eps:g} "
                                "(where patches meet)")
            steep = optional_number(r, "frames_seam_over_source_slope", summary_path)
            if steep > 0:
                failures.append(f"a source seam steeper than its source's 99th-percentile slope "
                                f"in view in {int(steep)} frames (largest "
                                f"{fmt(optional_number(r, 'seam_slope_max', summary_path), 2)}) "
                                f"at ε = {eps:g}")
            seam = optional_number(r, "shading_seam_levels_max", summary_path)
            if seam > SHADING_SEAM_VISIBLE_LEVELS:
                failures.append(f"shading steps where patches meet: {fmt(seam, 2)} levels more "
                                f"than inside patches (largest frame) at ε = {eps:g}")
            unsettled = n("frames_unsettled") if "frames_unsettled" in r else 0
            if unsettled > 0:
                failures.append(f"streaming never settled in {int(unsettled)} of {int(n('frames'))} "
                                f"frames at ε = {eps:g} (its view needs more than the GPU pool "
                                "holds): measured as drawn")
            unmeasurable = n("non_finite_pixels_total") if "non_finite_pixels_total" in r else 0
            if unmeasurable > 0:
                failures.append(f"{int(unmeasurable)} unmeasurable pixels at ε = {eps:g}")
        if failures:
            lines.append(f"- **{method}** fails: " + "; ".join(failures) + ".")
        else:
            lines.append(f"- **{method}**: no failure on this flight (within ε + {tol:g} px, no crack, "
                         "nothing unmeasurable).")
    # Popping is a degree, not a failure: every method that changes its mesh pops some.
    popping = {m: max((number(r, "popping_levels_mean", summary_path) for r in rows
                       if not math.isnan(number(r, "popping_levels_mean", summary_path))), default=math.nan)
               for m, rows in methods.items()}
    ranked = sorted((m for m, v in popping.items() if not math.isnan(v)), key=lambda m: -popping[m])
    if ranked:
        lines += ["", "Popping (the LOD image's change beyond the reference's, 8-bit levels a frame, "
                  "the largest over ε), most first: "
                  + ", ".join(f"{m} {fmt(popping[m], 3)}" for m in ranked) + "."]
    lines += ["", "Measured on this flight only; the stability suite (AccuracyStabilityTest) "
              "flies every method through the cases where LOD methods break.", ""]
    return lines


def stability_section(bench, rows, path, tol):
    """terrain-bench --stability: every method and threshold at the stress poses found in the
    pyramid (stability.csv), and in plain words where each method fails there: error over
    ε + tol, crack pixels, unmeasurable pixels, or a view that never settled."""
    if not rows:
        return []
    info = (bench or {}).get("method_info", {})
    poses = (bench or {}).get("stability", {}) or {}
    pose_names = []
    for r in rows:
        if r["pose"] not in pose_names:
            pose_names.append(r["pose"])
    lines = ["## Where each method fails at the stress poses", "",
             "The cases where LOD methods break, found in this pyramid (`terrain-bench "
             "--stability`): each method at each ε, once, settled.", ""]
    for p in poses.get("poses", []):
        lines.append(f"- **{p['name']}**: {p['what']}.")
    lines += ["", "Each cell: the largest measured error as a multiple of ε over the thresholds, "
              f"✗ where it exceeds ε + {tol:g} px; crack and unmeasurable pixels when there are any.", "",
              "| method | " + " | ".join(pose_names) + " |", "|---|" + "---|" * len(pose_names)]
    by_method_pose = {}
    for r in rows:
        by_method_pose.setdefault(r["method"], {}).setdefault(r["pose"], []).append(r)
    failures_by_method = {}
    for method, per_pose in by_method_pose.items():
        cells, failures = [], []
        for pose in pose_names:
            worst, over, cracks, unmeasurable, unsettled = 0.0, [], 0, 0, 0
            for r in per_pose.get(pose, []):
                n = lambda key: number(r, key, path)
                eps = n("threshold_px")
                err = n("error_max_px")
                if not math.isnan(err):
                    worst = max(worst, err / eps)
                if n("non_finite_pixels") > 0 or (not math.isnan(err) and err > eps + tol):
                    over.append(f"{fmt(err)} px at ε = {eps:g}")
                cracks += int(n("crack_pixels"))
                unmeasurable += int(n("non_finite_pixels"))
                unsettled += 0 if r.get("settled", "1") == "1" else 1
            cell = f"{fmt(worst)} ε" + (" ✗" if over else "")
            if cracks:
                cell += f", {cracks} crack px"
            if unmeasurable:
                cell += f", {unmeasurable} unmeasurable"
            cells.append(cell if per_pose.get(pose) else "–")
            bounds = info.get(base_method(method), {}).get("bounds_error", True)
            if over:
                failures.append(f"at the {pose} pose, over ε + {tol:g} px ({'; '.join(over)})"
                                + ("" if bounds else " — it promises no bound"))
            if cracks:
                failures.append(f"{cracks} crack pixel{'s' if cracks != 1 else ''} at the {pose} pose")
            if unmeasurable:
                failures.append(f"{unmeasurable} unmeasurable pixel{'s' if unmeasurable != 1 else ''} "
                                f"at the {pose} pose")
            if unsettled:
                failures.append(f"streaming did not settle at the {pose} pose (measured as drawn)")
        lines.append(f"| {method} | " + " | ".join(cells) + " |")
        failures_by_method[method] = failures
    lines.append("")
    for method, failures in failures_by_method.items():
        if failures:
            lines.append(f"- **{method}** fails: " + "; ".join(failures) + ".")
        else:
            lines.append(f"- **{method}**: no failure at the stress poses.")
    lines.append("")
    return lines


def write_report(out_dir, bench, summary_rows, charts, summary_path, stability_rows=None,
                 stability_path="", ratios=None):
    lines = ["# Speed against accuracy", ""]
    if bench:
        surface = (f"{bench['raster']['width']} × {bench['raster']['height']} samples, "
                   f"{bench['raster']['levels']} levels of {bench['raster']['patch_samples']}-sample "
                   f"patches ({bench['raster']['block_quads']}-quad blocks)"
                   if "raster" in bench else "a globe pyramid measured against its sources")
        lines += [f"Pyramid `{bench.get('pyramid')}`, {surface}; "
                  f"{bench['frames']} frames of {bench['width_px']} × {bench['height_px']} px on the "
                  f"{'default' if bench['path'] == 'default' else bench['path']} camera path "
                  f"({bench['path_duration_s']:g} s), "
                  f"{'streaming settled before each frame' if bench['settle'] else 'frames drawn as streaming had them'}; "
                  f"renderer {bench['gl']['renderer']} ({bench['gl']['version']}).", "",
                  "Made by:", "", "```sh", bench.get("command", ""), "```", ""]
        if bench.get("gpu_ms_source") == "llvmpipe-cpu":
            lines += ["**GPU ms are CPU figures here**: llvmpipe rasterises on the CPU, and "
                      "GL_TIME_ELAPSED measures that work, not a GPU.", ""]
    tol = bench.get("tolerance_px", 0.05) if bench else 0.05
    lines += ["## Per threshold", "",
              "| method | ε px | triangles | patches | draw calls | LOD µs | GPU ms | frame ms | "
              "resident MiB | error max px | median frame max px | mean px | frames > ε+tol | "
              "PSNR dB (min) | cracks | boundary artefacts | shading seam | popping |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in summary_rows:
        n = lambda key: number(r, key, summary_path)
        lines.append(
            f"| {r['method']} | {n('threshold_px'):g} | {fmt(n('triangles_mean'), 0)} | "
            f"{fmt(n('patches_mean'), 1)} | {fmt(n('draw_calls_max'), 0)} | {fmt(n('lod_update_us_mean'), 0)} | "
            f"{fmt(n('gpu_ms_mean'))} | {fmt(n('frame_ms_mean'))} | "
            f"{fmt(n('resident_bytes_max') / 1048576.0, 1)} | {fmt(n('error_max_px'))} | "
            f"{fmt(n('error_max_median_px'))} | {fmt(n('error_mean_px'), 3)} | "
            f"{fmt(n('frames_over_threshold'), 0)} / {fmt(n('frames'), 0)} | "
            f"{fmt(n('psnr_db_mean'), 1)} ({fmt(n('psnr_db_min'), 1)}) | "
            f"{fmt(n('crack_pixels_total'), 0)} | "
            f"{boundary_artefacts_cell(r, summary_path)} | "
            f"{fmt(optional_number(r, 'shading_seam_levels_max', summary_path), 2)} | "
            f"{fmt(n('popping_levels_mean'), 3)} |")
    lines += ["", f"*error*: measured screen-space error against the full-resolution reference "
              f"(largest over all frames, the median of the frames' largest, and the mean over "
              f"pixels); *frames > ε+tol*: frames whose largest error exceeds ε + {tol:g} px "
              f"(the rasterisation tolerance); *boundary artefacts*: pixels where two patches "
              f"meet that differ from both sides and from the reference (a pinhole, an edge "
              f"shaded wrong; – for a method that draws no patch ids), in brackets those at "
              f"silhouettes, which the LOD's own error may move and the detector cannot judge; "
              f"*shading seam*: how much "
              f"more the LOD's brightness steps between neighbouring pixels of two patches than "
              f"between neighbouring pixels of one patch, each against the reference's step "
              f"there (8-bit luma levels, the largest frame; a seam where levels meet); "
              f"*popping*: LOD image "
              f"change beyond the "
              f"reference's, in 8-bit levels. Definitions: docs/accuracy.md.", ""]
    if bench and bench.get("tiling") == "globe":
        lines += globe_section(bench)
    lines += method_sections(bench, summary_rows, summary_path, tol)
    lines += yardstick_ratio_table(ratios or {})
    lines += stability_section(bench, stability_rows or [], stability_path, tol)
    lines += ["## Charts", ""]
    for title, path in charts:
        lines += [f"### {title}", "", f"![{title}]({os.path.basename(path)})", ""]
    samples = sorted(f for f in os.listdir(out_dir) if f.startswith("sample-") and f.endswith(".png"))
    if samples:
        lines += ["## Sample frame", "", "The reference (full resolution) and the LOD at each ε:", ""]
        for f in samples:
            lines += [f"![{f}]({f})", ""]
    poses = sorted(f for f in os.listdir(out_dir) if f.startswith("stability-") and f.endswith(".png"))
    if poses:
        lines += ["## The stress poses", "", "The reference (full resolution) at each pose:", ""]
        for f in poses:
            lines += [f"![{f}]({f})", ""]
    path = os.path.join(out_dir, "report.md")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines))
    os.replace(path + ".tmp", path)
    return path


# --- Globe pyramids: the flight by height, and bench.json's "globe" figures ---------------

HORIZON_COMPARISON = "-no-horizon-culling"  # the globe's run without horizon culling


def globe_flights(frame_rows, frames_path):
    """The frames of each (method, ε) flown with horizon culling, in order: one curve each
    (the run without it is the comparison, in the table)."""
    flights = {}
    for row in frame_rows:
        if row["method"].endswith(HORIZON_COMPARISON):
            continue
        key = (row["method"], number(row, "threshold_px", frames_path))
        flights.setdefault(key, []).append(row)
    return flights


def chart_globe_by_height(flights, frames_path, out_dir, name, title, ylabel, series, log_y):
    """One curve per ε (and per series) of a per-frame figure against the camera's height."""
    fig, ax = plt.subplots(figsize=(7.2, 4.4))
    for (method, eps), rows in flights.items():
        heights = [max(number(r, "camera_height_m", frames_path), 1e-3) for r in rows]
        for key, style, label in series:
            x, y = finite(heights, [number(r, key, frames_path) for r in rows])
            prefix = "" if method == "yusov2011" else f"{method} "
            line, = ax.plot(x, y, style, lw=1.2, label=f"{prefix}ε={eps:g}{label}")
            if key.endswith("error_max_px") and style == "-":
                ax.axhline(eps, color=line.get_color(), lw=0.7, ls=":")
    ax.set_xscale("log")
    ax.invert_xaxis()  # from orbit down to the ground, left to right
    if log_y:
        ax.set_yscale("log")
    ax.set_xlabel("camera height above the ellipsoid (m)")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    return save(fig, out_dir, name)


def globe_charts(frame_rows, frames_path, out_dir):
    flights = globe_flights(frame_rows, frames_path)
    return [
        ("Measured error from orbit to the ground",
         chart_globe_by_height(flights, frames_path, out_dir, "globe_error_vs_height.png",
                               "Measured error from orbit to the ground",
                               "largest error (px); dotted: ε",
                               [("lod_error_max_px", "-", ": LOD (against the finest level)"),
                                ("error_max_px", "--", ": against the sources")], True)),
        ("PSNR against the reference image",
         chart_globe_by_height(flights, frames_path, out_dir, "globe_psnr_vs_height.png",
                               "PSNR against the globe reference image", "PSNR (dB)",
                               [("psnr_db", "-", "")], False)),
        ("Triangles per frame",
         chart_globe_by_height(flights, frames_path, out_dir, "globe_triangles_vs_height.png",
                               "Triangles per frame from orbit to the ground", "triangles",
                               [("triangles", "-", "")], True)),
    ]


def globe_section(bench):
    """The globe's own figures: the LOD's error apart from the sources', horizon culling on
    and off, the time to full detail after arriving, the same view at a pole, on the equator
    and over the cube, the seams between the sources, and what the pyramid stores."""
    globe = bench.get("globe") or {}
    lines = ["## The globe", "",
             "| method | ε px | LOD error max px | frames > ε+tol (LOD) | error vs sources max px "
             "| frames > ε+tol (sources) | cracks | horizon-culled | full detail after arriving |",
             "|---|---|---|---|---|---|---|---|---|"]
    for t in bench.get("thresholds", []):
        arrival = t.get("full_detail_after_arrival")
        culled = t.get("horizon_culled_fraction")
        lines.append(
            f"| {t['method']} | {t['threshold_px']:g} | {fmt(t.get('lod_error_max_px'))} | "
            f"{t['lod_frames_over_threshold']} / {t['frames']} | {fmt(t.get('error_max_px'))} | "
            f"{t['frames_over_threshold']} / {t['frames']} | {t['crack_pixels_total']} | "
            f"{fmt(None if culled is None else 100.0 * culled, 1)} % | "
            f"{str(arrival['frames']) + ' frames' if arrival else 'not reached'} |")
    lines += ["", "*LOD error*: against the pyramid's finest level, what the LOD chose; *error vs "
              "sources*: against the DEMs themselves, which adds the finest level's resampling "
              "of them (it shows close to the ground, docs/globe.md); *cracks*: against the "
              f"globe reference image (every finest sample a vertex); the `{HORIZON_COMPARISON}` "
              "run flies the same path with horizon culling off. Sources: "
              f"{', '.join('`' + s + '`' for s in globe.get('sources', []))}.", ""]
    same = globe.get("same_view_straight_down_10km")
    if same:
        lines += ["### The same view at a pole, on the equator and over the cube", "",
                  "| place | patches | data patches |", "|---|---|---|"]
        lines += [f"| {v['place']} | {v['patches']} | {v['data_patches']} |" for v in same]
        lines.append("")
    seams = globe.get("seams")
    if seams:
        lines += ["### Seams between the sources", "",
                  "Where a finer source ends over a coarser one it is blended into it across a band "
                  "that follows the height step there (docs/globe.md, \"How it works\"): *seam slope* "
                  "is the largest slope that blend adds, against the source's own 99th-percentile "
                  "slope (the target: no steeper) and against its 99th-percentile slope over a "
                  "baseline as wide as the band (*band scale*, ≤ 1 unless the band is capped).", "",
                  "| source | band px | band km | largest step m | seam slope | 99th pct slope "
                  "| band scale | capped px |", "|---|---|---|---|---|---|---|---|"]
        for seam in seams:
            lines.append(
                f"| `{seam['input']}` | {seam['bandPixels'][0]:.0f}–{seam['bandPixels'][1]:.0f} | "
                f"{seam['bandMetres'][0] / 1e3:.1f}–{seam['bandMetres'][1] / 1e3:.1f} | "
                f"{seam['largestStepM']:.0f} | {seam['seamSlope']:.3f} | "
                f"{seam['sourceSlopeP99']:.3f} | {seam['bandScaleRatio']:.2f} | "
                f"{seam['cappedPixels']} |")
        lines.append("")
        for seam in seams:
            if not seam["withinSourceSlopes"]:
                lines.append(f"- **The seam of `{seam['input']}` fails**: its blend adds a slope of "
                             f"{seam['seamSlope']:.3f}, steeper than the source's 99th-percentile "
                             f"slope {seam['sourceSlopeP99']:.3f}: a wall along its edge.")
            elif seam["bandScaleRatio"] > 1.0:
                lines.append(f"- **The seam of `{seam['input']}` stands out**: its blend adds "
                             f"{seam['bandScaleRatio']:.2f} times the source's 99th-percentile "
                             f"slope over the band's width"
                             + (f" (the band is capped along {seam['cappedPixels']} pixels)"
                                if seam["cappedPixels"] else "") + ".")
        lines.append("")
    storage = globe.get("storage")
    if storage:
        lines += [f"Stored samples, all levels: {storage['stored_samples_all_levels']:,}; the "
                  f"finest level over the whole globe would hold "
                  f"{storage['finest_level_samples_whole_globe']:,.0f}, a longitude/latitude grid "
                  f"of the same equatorial spacing "
                  f"{storage['lon_lat_grid_same_equatorial_spacing']:,.0f} "
                  f"(ratio {storage['whole_globe_ratio']:g}).", ""]
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bench-dir", help="terrain-bench's output folder (summary.csv, frames.csv, telemetry, bench.json)")
    parser.add_argument("--summary", action="append", default=[], help="summary CSV (repeatable: one or more methods each)")
    parser.add_argument("--frames", help="per-frame CSV, for the error timeline")
    parser.add_argument("--telemetry", help="telemetry CSV (docs/telemetry.md), for the timeline")
    parser.add_argument("--out", required=True, help="folder for the PNGs (and report.md)")
    parser.add_argument("--report", action="store_true", help="also write report.md")
    parser.add_argument("--check", action="store_true",
                        help="only check that matplotlib loads (exit status 0) and stop")
    if "--check" in sys.argv[1:]:
        return  # the imports above succeeded
    args = parser.parse_args()

    bench = None
    summaries = list(args.summary)
    frames = args.frames
    telemetry = args.telemetry
    if args.bench_dir:
        summaries.insert(0, os.path.join(args.bench_dir, "summary.csv"))
        frames = frames or os.path.join(args.bench_dir, "frames.csv")
        bench_json = os.path.join(args.bench_dir, "bench.json")
        if os.path.exists(bench_json):
            with open(bench_json) as f:
                bench = json.load(f)
    if not summaries and not telemetry:
        fail("give --bench-dir, --summary or --telemetry")
    os.makedirs(args.out, exist_ok=True)

    charts = []
    summary_rows = []
    if summaries:
        for path in summaries:
            summary_rows += read_csv(path)
        methods = by_method(summary_rows)
        source = ", ".join(summaries)
        charts.append(("Triangles against measured error", chart_triangles_vs_error(methods, args.out, source)))
        charts.append(("Frame time against measured error", chart_frame_time_vs_error(methods, args.out, source)))
        charts.append(("PSNR against triangles", chart_psnr_vs_triangles(methods, args.out, source)))
    ratios = {}
    if frames and os.path.exists(frames):
        frame_rows = read_csv(frames)
        charts.append(("Measured error along the flight", chart_error_timeline(frame_rows, args.out, frames)))
        if bench and bench.get("tiling") == "globe":
            charts += globe_charts(frame_rows, frames, args.out)
        ratios = yardstick_ratios(frame_rows, frames)
        if ratios:
            charts.append((f"Triangles against the {YARDSTICK} yardstick, frame by frame",
                           chart_yardstick_ratio(ratios, args.out)))
    if telemetry is None and args.bench_dir and summary_rows:
        # The flight at the threshold nearest Yusov's 2 px.
        thresholds = sorted({number(r, "threshold_px") for r in summary_rows}, key=lambda t: abs(t - 2.0))
        candidate = os.path.join(args.bench_dir, f"telemetry-eps-{thresholds[0]:g}.csv")
        telemetry = candidate if os.path.exists(candidate) else None
    if telemetry:
        charts.append(("Streaming telemetry", chart_telemetry_timeline(read_csv(telemetry), args.out, telemetry)))
    if args.report:
        if not summary_rows:
            fail("--report needs a summary CSV")
        stability_path = os.path.join(args.bench_dir, "stability.csv") if args.bench_dir else ""
        stability_rows = read_csv(stability_path) if stability_path and os.path.exists(stability_path) else []
        write_report(args.out, bench, summary_rows, charts, ", ".join(summaries), stability_rows,
                     stability_path, ratios)
    for _, path in charts:
        print(path)


if __name__ == "__main__":
    main()
