#!/usr/bin/env python3
"""Time to full detail after a teleport, from a folder and over HTTP (issue 49).

For each pyramid, serves its folder with Debian's nginx on 127.0.0.1 behind
terrain-test-proxy (tests/tools/TestProxy.cpp: a latency before every answer, with
--drop-every every N-th request's connection closed unanswered, and with --loss-percent P that
share of the packets lost, each loss stalling its stream a round trip, or 200 ms near a
transfer's end, as TCP's retransmissions do; answers go out a congestion window at a time,
from --initial-window segments (10, Linux's) doubling each round trip, halved by a loss, so a
large file takes round trips as over a real network; with --link-mbps M every connection
shares one link of M megabits a second, as a user's line), then, alternating with and
without reading ahead (--no-prefetch), runs

  terrain-render PYRAMID_OR_URL --frames 1 --every 0 --error-px E --json

with an empty disk cache (TERRAIN_CACHE_DIR, a new folder each run): the first frame at the
default path's start is drawn with nothing loaded, then terrain-render draws frames 1/60 s
apart at the least until the heights are at full detail (full_detail_after_arrival). A
teleport's frames are that first frame and the arrival's (1 + heights.frames); its seconds
are the arrival's (heights.seconds, from the end of the first frame): the first frame's
drawing, which on llvmpipe includes compiling the shaders (about a second), is no cost of a
teleport in a running viewer and is left out (its reads have begun by then). Writes OUT/remote-arrival-bench.json and .md
with the median and worst of the repeats. Rerun with:

  tools/bench/remote_arrival_bench.py --build build --out out/bench PYRAMID...

Globe pyramids: --pose LAT,LON,ALTITUDE,PITCH teleports to that pose (terrain-render --lat
--lon --altitude --pitch) instead of the default path's start, an orbit far above the data.
"""
import argparse
import json
import os
import platform
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

NGINX = "/usr/sbin/nginx"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Nginx:
    """nginx in the foreground serving `root` on a free port, every path in a temporary folder."""

    def __init__(self, root):
        self.dir = tempfile.mkdtemp(prefix="arrival-nginx-")
        self.port = free_port()
        conf = Path(self.dir) / "nginx.conf"
        d = self.dir
        conf.write_text(
            f"worker_processes 1;\ndaemon off;\nmaster_process off;\npid {d}/nginx.pid;\n"
            f"error_log {d}/error.log;\nevents {{ worker_connections 256; }}\nhttp {{\n"
            f"  access_log off;\n  client_body_temp_path {d}/body;\n  proxy_temp_path {d}/proxy;\n"
            f"  fastcgi_temp_path {d}/fastcgi;\n  uwsgi_temp_path {d}/uwsgi;\n"
            f"  scgi_temp_path {d}/scgi;\n"
            f"  server {{ listen 127.0.0.1:{self.port}; root {root}; }}\n}}\n")
        self.process = subprocess.Popen([NGINX, "-p", d, "-c", str(conf), "-e", f"{d}/error.log"])
        for _ in range(200):
            try:
                socket.create_connection(("127.0.0.1", self.port), timeout=0.1).close()
                return
            except OSError:
                if self.process.poll() is not None:
                    break
                subprocess.run(["sleep", "0.05"])
        raise RuntimeError(f"nginx did not start; see {d}/error.log")

    def stop(self):
        self.process.terminate()
        self.process.wait()
        shutil.rmtree(self.dir, ignore_errors=True)


class Proxy:
    def __init__(self, program, upstream, latency_ms, drop_every, loss_percent, window=0,
                 link_mbps=0.0):
        self.process = subprocess.Popen(
            [program, str(upstream), str(latency_ms), str(drop_every), str(loss_percent),
             str(window), str(link_mbps)],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        line = self.process.stdout.readline().split()
        if len(line) != 2 or line[0] != "port":
            raise RuntimeError("terrain-test-proxy did not start")
        self.port = int(line[1])

    def stop(self):
        self.process.stdin.close()
        self.process.wait()


def teleport(render, location, error_px, prefetch, size, pose):
    """One run: (frames, seconds) to full detail of the heights, or None if not reached."""
    with tempfile.TemporaryDirectory(prefix="arrival-") as work:
        env = dict(os.environ, TERRAIN_CACHE_DIR=str(Path(work) / "cache"))
        command = [render, location, "--frames", "1", "--every", "0", "--error-px", str(error_px),
                   "--width", str(size[0]), "--height", str(size[1]), "-o", str(Path(work) / "out"),
                   "--json"]
        if not prefetch:
            command.append("--no-prefetch")
        if pose:
            for flag, value in zip(("--lat", "--lon", "--altitude", "--pitch"), pose):
                command += [flag, value]
        done = subprocess.run(command, env=env, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(command)} failed:\n{done.stderr}")
        arrival = json.loads(done.stdout).get("full_detail_after_arrival")
        if not arrival:
            return None
        return 1 + arrival["heights"]["frames"], arrival["heights"]["seconds"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("pyramids", nargs="+", type=Path)
    parser.add_argument("--build", type=Path, default=Path("build"))
    parser.add_argument("--out", type=Path, default=Path("out/bench"))
    parser.add_argument("--latencies-ms", default="0,50,200")
    parser.add_argument("--drop-every", type=int, default=10,
                        help="also a run at 50 ms with every N-th request dropped (0: none)")
    parser.add_argument("--loss-percent", type=float, default=1.0,
                        help="also a run at 50 ms losing this share of packets, each loss "
                             "stalling its stream as TCP's retransmissions do (0: none)")
    parser.add_argument("--initial-window", type=int, default=10,
                        help="TCP's congestion window in segments as a connection starts or "
                             "resumes after idling, doubling each round trip (slow start; "
                             "Linux's 10); 0: answers go out at once, at no bandwidth cost")
    parser.add_argument("--link-mbps", type=float, default=0.0,
                        help="one link of this many megabits a second shared by every "
                             "connection, as a user's line (0: no cap; needs a window)")
    parser.add_argument("--error-px", type=float, default=2.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--size", default="960x540")
    parser.add_argument("--pose", default="",
                        help="LAT,LON,ALTITUDE,PITCH: where a globe pyramid's teleport goes")
    args = parser.parse_args()
    pose = args.pose.split(",") if args.pose else []
    if pose and len(pose) != 4:
        parser.error("--pose takes LAT,LON,ALTITUDE,PITCH")
    render = str(args.build / "tools/terrain-render/terrain-render")
    proxy_program = str(args.build / "tests/tools/terrain-test-proxy")
    size = tuple(int(v) for v in args.size.split("x"))
    settings = [("folder", None, 0, 0.0)]
    settings += [(f"HTTP {ms} ms", int(ms), 0, 0.0) for ms in args.latencies_ms.split(",") if ms]
    if args.drop_every > 0:
        settings.append((f"HTTP 50 ms, 1 request in {args.drop_every} dropped", 50, args.drop_every,
                         0.0))
    if args.loss_percent > 0:
        settings.append((f"HTTP 50 ms, {args.loss_percent:g} % of packets lost", 50, 0,
                         args.loss_percent))
    rows = []
    for pyramid in args.pyramids:
        pyramid = pyramid.resolve()
        server = Nginx(pyramid.parent)
        try:
            for name, latency, drop, loss in settings:
                proxy = (None if latency is None
                         else Proxy(proxy_program, server.port, latency, drop, loss,
                                    args.initial_window, args.link_mbps))
                location = (str(pyramid) if proxy is None
                            else f"http://127.0.0.1:{proxy.port}/{pyramid.name}")
                runs = {True: [], False: []}
                for _ in range(args.repeats):
                    for prefetch in (False, True):
                        runs[prefetch].append(teleport(render, location, args.error_px, prefetch, size,
                                                        pose))
                if proxy:
                    proxy.stop()
                for prefetch in (False, True):
                    got = [r for r in runs[prefetch] if r is not None]
                    row = {"pyramid": pyramid.name, "network": name, "prefetch": prefetch,
                           "runs": len(runs[prefetch]), "reached": len(got)}
                    if got:
                        row.update(frames_median=statistics.median(r[0] for r in got),
                                   frames_max=max(r[0] for r in got),
                                   seconds_median=statistics.median(r[1] for r in got),
                                   seconds_max=max(r[1] for r in got))
                    rows.append(row)
                    print(json.dumps(row), file=sys.stderr)
        finally:
            server.stop()
    args.out.mkdir(parents=True, exist_ok=True)
    report = {"machine": {"cpus": os.cpu_count(), "platform": platform.platform()},
              "initial_window": args.initial_window, "link_mbps": args.link_mbps or None,
              "error_px": args.error_px, "size": args.size, "repeats": args.repeats,
              "pose": args.pose or None, "rows": rows}
    (args.out / "remote-arrival-bench.json").write_text(json.dumps(report, indent=1) + "\n")
    lines = ["| pyramid | network | read ahead | frames (median, worst) | seconds (median, worst) |",
             "|---|---|---|---|---|"]
    for r in rows:
        if r["reached"] == 0:
            figures = "not reached | not reached"
        else:
            figures = (f"{r['frames_median']:g}, {r['frames_max']:g} | "
                       f"{r['seconds_median']:.3f}, {r['seconds_max']:.3f}")
        lines.append(f"| {r['pyramid']} | {r['network']} | {'yes' if r['prefetch'] else 'no'} | "
                     f"{figures} |")
    (args.out / "remote-arrival-bench.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
