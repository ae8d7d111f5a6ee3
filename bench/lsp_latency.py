#!/usr/bin/env python3
# Time from `didChange` to `publishDiagnostics` in `wsd lsp`: the Cornell box, and a generated
# scene with an inline mesh of about 1,000,000 triangles. Each run sends the whole text again
# (full sync) with one comment changed and waits for that version's diagnostics.
# Usage: bench/lsp_latency.py WSD [--runs N] [--triangles N]   (prints measured numbers only)
import argparse
import math
import os
import statistics
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "app"))
from lsp_client import Client  # noqa: E402


def mesh_scene(triangles):
    n = max(2, math.ceil(math.sqrt(triangles / 2)) + 1)  # n×n vertices, 2(n-1)² triangles
    verts = ", ".join("<%d, %d, %d>" % (i - n // 2, j - n // 2, (i * j) % 7) for j in range(n) for i in range(n))
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            faces.append("<%d, %d, %d>, <%d, %d, %d>" % (a, a + 1, a + n + 1, a, a + n + 1, a + n))
    text = ("camera { position <0, 0, -%d>  look_at <0, 0, 0>  fov 60 }\n"
            "light point { position <0, %d, -%d> }\n"
            "mesh {\n  vertices [%s]\n  faces [%s]\n  material material { color <0.8, 0.8, 0.8> }\n}\n"
            % (2 * n, n, n, verts, ", ".join(faces)))
    return text, 2 * (n - 1) ** 2


def measure(wsd, path, text, runs):
    uri = "file://" + os.path.abspath(path)
    c = Client(wsd, cwd=os.path.dirname(os.path.abspath(path)))
    c.initialize()
    start = time.monotonic()
    c.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "wsd", "version": 1, "text": text}})
    diags = c.wait_diagnostics(uri, 1, timeout=600)["diagnostics"]
    opened = time.monotonic() - start
    times = []
    for k in range(runs):
        edited = text + "\n// edit %d\n" % k
        start = time.monotonic()
        c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": k + 2},
                                            "contentChanges": [{"text": edited}]})
        c.wait_diagnostics(uri, k + 2, timeout=600)
        times.append(time.monotonic() - start)
    c.close()
    return opened, times, len(diags)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("wsd")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--triangles", type=int, default=1000000)
    a = ap.parse_args()
    wsd = os.path.abspath(a.wsd)
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    cornell = os.path.join(root, "examples", "cornell.wsd")
    with open(cornell, encoding="utf-8") as f:
        cases = [("cornell.wsd", cornell, f.read(), None)]
    with tempfile.TemporaryDirectory() as tmp:
        text, tris = mesh_scene(a.triangles)
        path = os.path.join(tmp, "mesh.wsd")
        cases.append(("mesh.wsd", path, text, tris))
        for name, path, text, tris in cases:
            opened, times, count = measure(wsd, path, text, a.runs)
            ms = [t * 1000 for t in times]
            print("%s  %s triangles  %.1f MB  didOpen %.0f ms  didChange->publishDiagnostics median %.0f ms"
                  "  range %.0f-%.0f ms  runs %d  diagnostics %d"
                  % (name, tris if tris else "-", len(text.encode()) / 1e6, opened * 1000,
                     statistics.median(ms), min(ms), max(ms), len(ms), count))


main()
