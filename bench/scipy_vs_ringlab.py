#!/usr/bin/env python3
"""Times the paper ring from start to flat with scipy's DOP853 and with ringlab, side by side.

Same equations (eqs. 3-5 of the paper, PHYSICS.md), same case, same tolerances
(rtol 1e-10, atol 1e-12), same end (theta = pi/2 - 0.02).

    python3 -m venv bench/.venv && bench/.venv/bin/pip install scipy
    cargo build --release
    bench/.venv/bin/python bench/scipy_vs_ringlab.py

`ringlab bench --scipy bench/.venv/bin/python` runs this script with `--scipy-only --json`
(scipy's side alone, as JSON) and measures ringlab's side itself, in the same run.
"""
import argparse
import json
import math
import subprocess
import sys
import time
from pathlib import Path

try:
    import numpy as np
    from scipy.integrate import solve_ivp
except ImportError as e:
    print(f"{sys.executable} has no {e.name}: python3 -m venv bench/.venv && "
          "bench/.venv/bin/pip install scipy", file=sys.stderr)
    sys.exit(3)

R, H, W = 1.025, 0.88, 0.05
G = R * 4.5**2 / 20.2
C = np.array([0.03, 0.063, 0.085])
RI = R - W
I1 = (R**2 + RI**2) / 4 + H**2 / 12
I2 = (R**2 + RI**2) / 2
INERTIA = np.array([I1, I2, I1])
J = np.diag(INERTIA) + np.array([[H**2 / 4 + R**2, 0, 0], [0, R**2, -H * R / 2], [0, -H * R / 2, H**2 / 4]])
J_INV = np.linalg.inv(J)
R_G = np.array([0.0, H / 2, R])


def rhs(_t, y):
    phi, theta, _psi, w1, w2, w3 = y[:6]
    st, ct = math.sin(theta), math.cos(theta)
    w = np.array([w1, w2, w3])
    om = np.array([w1, w3 * st / ct, w3])
    v_c = np.cross(w, R_G)
    f = -np.cross(om, INERTIA * w) - np.cross(R_G, np.cross(om, v_c))
    f[0] += G * (R * st - H / 2 * ct)
    wd = J_INV @ f - C * np.abs(w) * w
    sp, cp = math.sin(phi), math.cos(phi)
    along = v_c[1] * ct - v_c[2] * st
    return [w3 / ct, w1, w2 - w3 * st / ct, wd[0], wd[1], wd[2], v_c[0] * cp - along * sp, v_c[0] * sp + along * cp]


def flat(_t, y):
    return y[1] - (math.pi / 2 - 0.02)


flat.terminal = True
flat.direction = 1


def time_scipy():
    """One solve: wall and CPU seconds, evaluations and the end time."""
    theta0, phidot0 = 0.55, 4.5
    y0 = [-0.38, theta0, 0.0, 0.0, phidot0 * math.sin(theta0), phidot0 * math.cos(theta0), 0.0, 0.0]
    clock, cpu = time.perf_counter(), time.process_time()
    sol = solve_ivp(rhs, (0, 1000), y0, method="DOP853", rtol=1e-10, atol=1e-12, events=flat)
    wall, cpu = time.perf_counter() - clock, time.process_time() - cpu
    t_end = sol.t_events[0][0] if len(sol.t_events[0]) else sol.t[-1]
    return {"seconds": wall, "cpu_seconds": cpu, "evaluations": int(sol.nfev), "t_end": float(t_end)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scipy-only", action="store_true", help="time scipy alone")
    parser.add_argument("--json", action="store_true", help="print scipy's figures as JSON")
    parser.add_argument("--repeats", type=int, default=1, help="solves; the fastest is reported")
    args = parser.parse_args()
    runs = [time_scipy() for _ in range(max(args.repeats, 1))]
    best = min(runs, key=lambda r: r["seconds"])
    best["repeats"] = len(runs)
    best["versions"] = {"python": sys.version.split()[0], "numpy": np.__version__,
                        "scipy": __import__("scipy").__version__}
    if args.json:
        print(json.dumps(best))
    else:
        print(f"scipy DOP853: {best['seconds']:.2f} s ({best['cpu_seconds']:.2f} s of CPU), "
              f"{best['evaluations']} evaluations, ends at t = {best['t_end']:.4f}")
    if args.scipy_only:
        return
    exe = Path(__file__).resolve().parent.parent / "target" / "release" / "ringlab"
    out = subprocess.run([str(exe), "bench", "--skip-sweep", "--skip-effects", "--json"],
                         check=True, capture_output=True, text=True)
    r = json.loads(out.stdout)
    ms = r["run_to_rest_ms"]
    print(f"ringlab:      {ms:.2f} ms, {r['run_rhs_evaluations']} evaluations, ends at t = {r['run_t_end']:.4f}")
    print(f"ringlab is {best['seconds'] * 1e3 / ms:.0f} times faster")


if __name__ == "__main__":
    main()
