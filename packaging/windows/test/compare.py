"""Compare two `ringlab ... --json` outputs (the Linux binary's and ringlab.exe's under Wine).

    python3 compare.py simulate linux.json wine.json [--markdown table.md]
    python3 compare.py fit linux.json wine.json [--markdown table.md]

Every number in the JSON, at any depth, is compared; strings, booleans and nulls must be
equal. Wall-clock fields (compute_seconds, seconds, timings, threads) are left out.

`simulate`: relative tolerance --rtol (1e-7). The two binaries' maths libraries (glibc's and
MinGW's) differ in the last bit of about 0.1% of sin, cos, exp, pow results; the adaptive
step-size control turns that into another sequence of steps (rhs_evaluations, steps and
rejected_steps differ by a few per cent: shown, not compared), and the results then differ by
what the integrator's own tolerance (rtol 1e-10 per step, paper-ring) lets through: up to
~2e-8 relative over a run. How many fields differ beyond 1e-9 is said too.
`fit`: the digits `ringlab fit` prints without --json (5 decimals), i.e.
|a - b| <= 5e-6 * max(1, |a|).
Exit status 1 on any difference beyond tolerance.
"""

import argparse
import json
import math
import sys

SKIP = ("seconds", "timing", "threads", "elapsed")
# The integrator's bookkeeping: it follows the last bits of every step (see above).
COUNTERS = ("steps", "rejected_steps", "rhs_evaluations")


def leaves(value, path=""):
    if isinstance(value, dict):
        for k, v in value.items():
            if any(s in k.lower() for s in SKIP):
                continue
            yield from leaves(v, f"{path}.{k}" if path else k)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from leaves(v, f"{path}[{i}]")
    else:
        yield path, value


def agree(kind, rtol, a, b):
    """(ok, relative difference, the difference the tolerance measures), None where not numbers."""
    is_num = lambda x: isinstance(x, (int, float)) and not isinstance(x, bool)
    if not (is_num(a) and is_num(b)):
        return a == b, None, None
    if a == b:
        return True, 0.0, 0.0
    if not (math.isfinite(a) and math.isfinite(b)):
        return False, None, None
    diff = abs(a - b)
    rel = diff / max(abs(a), abs(b))
    if kind == "simulate":
        return rel <= rtol, rel, rel
    scaled = diff / max(1.0, abs(a))
    return scaled <= 5e-6, rel, scaled


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("kind", choices=["simulate", "fit"])
    ap.add_argument("linux")
    ap.add_argument("wine")
    ap.add_argument("--markdown", help="write the table here too")
    ap.add_argument("--rtol", type=float, default=1e-7, help="simulate's relative tolerance")
    args = ap.parse_args()
    try:
        with open(args.linux) as f:
            lin = json.load(f)
        with open(args.wine) as f:
            win = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        sys.exit(f"compare.py: cannot read the outputs: {e}")

    a, b = dict(leaves(lin)), dict(leaves(win))
    rows, bad, beyond_1e9, worst = [], 0, 0, (0.0, "")
    for key in sorted(set(a) | set(b)):
        if key not in a or key not in b:
            rows.append((key, a.get(key, "(missing)"), b.get(key, "(missing)"), "", "MISSING"))
            bad += 1
            continue
        ok, rel, measured = agree(args.kind, args.rtol, a[key], b[key])
        if args.kind == "simulate" and key in COUNTERS:
            verdict = "counter, not compared"
        else:
            bad += not ok
            verdict = "ok" if ok else "DIFFERS"
            if measured is not None:
                beyond_1e9 += measured > 1e-9
                worst = max(worst, (measured, key))
        rows.append((key, a[key], b[key], "" if rel is None else f"{rel:.1e}", verdict))

    tol = f"relative {args.rtol:g}" if args.kind == "simulate" else "5e-6 * max(1, |x|) (5 decimals)"
    measure = "relative difference" if args.kind == "simulate" else "|a - b| / max(1, |a|)"
    lines = [
        f"`{args.kind}`: {len(rows)} fields, {bad} beyond tolerance ({tol}); "
        f"{beyond_1e9} beyond 1e-9; the largest {measure} {worst[0]:.1e} (`{worst[1]}`)",
        "",
        "| field | Linux | Wine | relative difference | |",
        "|---|---|---|---|---|",
    ]
    for key, x, y, rel, verdict in rows:
        lines.append(f"| `{key}` | {x} | {y} | {rel} | {verdict} |")
    text = "\n".join(lines) + "\n"
    print(text, end="")
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
