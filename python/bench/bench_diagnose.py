#!/usr/bin/env python3
"""The cost of a diagnosis from Python against the CLI's, on the same recordings.

For each recording, rounds of (in alternating order, so that a machine's drift hits both):
  cli      `ringlab diagnose FILE --json`, the whole process (read, diagnose, print JSON);
  python   a Python process doing `ringlab.diagnose(ringlab.Recording.read(FILE))`, whole
           (interpreter start and `import ringlab` included);
  call     `ringlab.diagnose(rec)` alone, in this process.
Wall seconds and CPU seconds (every thread; the children's for the processes). The verdict is
the median ratio of the call to the CLI, wall and CPU, against 1.05 (the Python process adds
the interpreter's start and numpy's import, once per session: shown beside it). On a loaded
machine the wall times follow the load; the CPU times much less.

    python3 -m venv .venv && .venv/bin/pip install ./python
    cargo build --release
    .venv/bin/python python/bench/bench_diagnose.py [--rounds 3] [FILE ...]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

import ringlab

REPO = Path(__file__).resolve().parents[2]
DEFAULT = [REPO / "tests/data/independent/glitches.csv", REPO / "tests/data/independent/two-effects.csv"]


def children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed_process(argv: list[str]) -> tuple[float, float]:
    cpu0, t0 = children_cpu(), time.perf_counter()
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0, children_cpu() - cpu0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*", type=Path, default=DEFAULT)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--cli", type=Path, default=REPO / "target/release/ringlab")
    args = ap.parse_args()
    if not args.cli.is_file():
        print(f"no CLI at {args.cli}: cargo build --release", file=sys.stderr)
        return 2
    print(f"{os.cpu_count()} cores; load {os.getloadavg()[0]:.1f}; {args.rounds} rounds")
    verdicts = []
    for f in args.files:
        rec = ringlab.Recording.read(f)
        got: dict[str, list[tuple[float, float]]] = {"cli": [], "python": [], "call": []}
        for r in range(args.rounds):
            order = ["cli", "python", "call"] if r % 2 == 0 else ["call", "python", "cli"]
            for what in order:
                if what == "cli":
                    got[what].append(timed_process([str(args.cli), "diagnose", str(f), "--json"]))
                elif what == "python":
                    code = f"import ringlab; ringlab.diagnose(ringlab.Recording.read({str(f)!r}), progress=False)"
                    got[what].append(timed_process([sys.executable, "-c", code]))
                else:
                    cpu0, t0 = time.process_time(), time.perf_counter()
                    ringlab.diagnose(rec, progress=False)
                    got[what].append((time.perf_counter() - t0, time.process_time() - cpu0))
                wall, cpu = got[what][-1]
                print(f"{f.name:16} round {r} {what:6} wall {wall:7.3f} s  cpu {cpu:7.3f} s", flush=True)
        med = {k: (statistics.median(w for w, _ in v), statistics.median(c for _, c in v)) for k, v in got.items()}
        pct = lambda k, i: 100 * (med[k][i] / med["cli"][i] - 1)  # noqa: E731
        for i, what in ((0, "wall"), (1, "cpu ")):
            print(
                f"{f.name:16} median {what}: cli {med['cli'][i]:7.3f} s | call {med['call'][i]:7.3f} s "
                f"({pct('call', i):+5.1f}%) | python process {med['python'][i]:7.3f} s ({pct('python', i):+5.1f}%)"
            )
        verdicts.append(max(pct("call", 0), pct("call", 1)))
    worst = max(verdicts)
    print(f"the call against the CLI: worst {worst:+.1f}% ({'within' if worst <= 5 else 'OVER'} the 5% allowed)")
    return 0 if worst <= 5 else 1


if __name__ == "__main__":
    sys.exit(main())
