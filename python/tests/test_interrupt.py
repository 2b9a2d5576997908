"""Ctrl-C: SIGINT to a Python process in the middle of a diagnosis raises KeyboardInterrupt
there within a second (the core's cancel flag), and the interpreter goes on working."""

from __future__ import annotations

import signal
import subprocess
import sys
import time

from conftest import DATA

SCRIPT = f"""
import signal, sys, time
import ringlab
# Python leaves SIGINT ignored where it started so (a job put in the background by a shell
# without job control): Ctrl-C is taken as an interactive session takes it.
signal.signal(signal.SIGINT, signal.default_int_handler)
rec = ringlab.Recording.read({str(DATA / "independent" / "glitches.csv")!r})
print("ready", flush=True)
start = time.perf_counter()
try:
    ringlab.diagnose(rec, progress=False)
    print("finished", flush=True)
except KeyboardInterrupt:
    print(f"interrupted after {{time.perf_counter() - start:.2f}} s", flush=True)
# The interpreter is whole: the package still works, and Ctrl-C uncaught ends it as usual.
print("still", ringlab.simulate(t_end=1.0).end_reason, flush=True)
ringlab.diagnose(rec, progress=False)
"""


def test_sigint_cancels_a_diagnosis():
    proc = subprocess.Popen(
        [sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        assert proc.stdout is not None
        assert proc.stdout.readline().strip() == "ready"
        time.sleep(1.0)
        sent = time.perf_counter()
        proc.send_signal(signal.SIGINT)
        line = proc.stdout.readline().strip()
        stopped = time.perf_counter() - sent
        assert line.startswith("interrupted after"), line
        assert stopped < 2.0, f"{stopped:.2f} s from SIGINT to KeyboardInterrupt"
        assert proc.stdout.readline().strip() == "still t_end"
        time.sleep(1.0)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert "KeyboardInterrupt" in err
    assert "Traceback" in err and "panic" not in err.lower()
    # An uncaught KeyboardInterrupt ends Python as SIGINT does (-2) or with 1 on old versions.
    assert proc.returncode in (-signal.SIGINT, 1, 130), proc.returncode
