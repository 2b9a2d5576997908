#!/usr/bin/env python3
"""What takes the space in the page's .wasm: the code section's bytes per crate, from the
function names the module carries (its "name" section: the `web` profile strips it, so build
with `--profile release` for the table), and the data segments' bytes.
Usage: web/size-report.py [target/site/ringlab_web_bg.wasm]"""
import collections
import gzip
import re
import sys


def leb(b, i):
    """An unsigned LEB128 number at b[i]: (value, next index)."""
    v = shift = 0
    while True:
        x = b[i]
        i += 1
        v |= (x & 0x7F) << shift
        shift += 7
        if x < 0x80:
            return v, i


def sections(b):
    i = 8
    while i < len(b):
        sid = b[i]
        size, j = leb(b, i + 1)
        yield sid, b[j:j + size]
        i = j + size


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "target/site/ringlab_web_bg.wasm"
    b = open(path, "rb").read()
    if b[:4] != b"\0asm":
        sys.exit(f"{path}: not a WebAssembly module")
    imports = 0
    bodies = []
    names = {}
    data = 0
    for sid, body in sections(b):
        if sid == 2:  # imports: functions among them take the first indices
            n, i = leb(body, 0)
            for _ in range(n):
                for _ in range(2):
                    ln, i = leb(body, i)
                    i += ln
                kind = body[i]
                i += 1
                if kind == 0:
                    _, i = leb(body, i)
                    imports += 1
                elif kind == 1:
                    i += 1
                    flags, i = leb(body, i)
                    _, i = leb(body, i)
                    if flags & 1:
                        _, i = leb(body, i)
                elif kind == 2:
                    flags, i = leb(body, i)
                    _, i = leb(body, i)
                    if flags & 1:
                        _, i = leb(body, i)
                elif kind == 3:
                    i += 2
        elif sid == 10:  # code
            n, i = leb(body, 0)
            for _ in range(n):
                size, i = leb(body, i)
                bodies.append(size)
                i += size
        elif sid == 11:
            data = len(body)
        elif sid == 0:
            ln, i = leb(body, 0)
            if body[i:i + ln] != b"name":
                continue
            i += ln
            while i < len(body):
                sub = body[i]
                size, i = leb(body, i + 1)
                if sub == 1:
                    n, k = leb(body, i)
                    for _ in range(n):
                        idx, k = leb(body, k)
                        ln, k = leb(body, k)
                        names[idx] = body[k:k + ln].decode("utf-8", "replace")
                        k += ln
                i += size
    per_crate = collections.Counter()
    for k, size in enumerate(bodies):
        name = names.get(imports + k, "?")
        # "<T as Trait>::f" and "crate[hash]::path::f": the crate is the first path segment.
        name = name.lstrip("<&*_ ")
        crate = re.split(r"\[|::|<| ", name, maxsplit=1)[0] or "?"
        per_crate[crate] += size
    total = len(b)
    print(f"{path}: {total / 1e6:.2f} MB ({len(gzip.compress(b, 9)) / 1e6:.2f} MB gzipped); "
          f"code {sum(bodies) / 1e6:.2f} MB in {len(bodies)} functions, data {data / 1e6:.2f} MB")
    for crate, size in per_crate.most_common(20):
        print(f"  {size / 1e6:6.2f} MB  {crate}")


if __name__ == "__main__":
    main()
