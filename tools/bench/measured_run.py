"""measured_run: how the benchmark scripts run a measured command.

run(command, log) runs it with stdout captured and stderr to `log`, and returns
(wall seconds, CPU seconds, peak RSS bytes, stdout) of its whole process tree (os.wait4); a
command that fails ends the script with its exit status and its log.
"""
import os
import subprocess
import sys
import time
from pathlib import Path


def run(command, log):
    start = time.monotonic()
    with open(log, "w") as err:
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=err, text=True)
        stdout = process.stdout.read()
        _, status, usage = os.wait4(process.pid, 0)
    seconds = time.monotonic() - start
    code = os.waitstatus_to_exitcode(status)
    if code != 0:
        sys.exit(f"failed ({code}): {' '.join(map(str, command))}\n{Path(log).read_text()}")
    return seconds, usage.ru_utime + usage.ru_stime, usage.ru_maxrss * 1024, stdout
