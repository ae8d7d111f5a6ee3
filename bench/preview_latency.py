"""Save-to-pixels latency of `wsd preview`: starts it on a copy of a scene, follows its event
stream (/events) as the page does, and for each of N edits (a colour toggled in the scene file)
measures (while the previous render is still refining, as when editing) the time from the write to the first image of the new render fetched from /image (the
coarse first stage), and to the `loading` event (the save noticed). Prints one line per edit and
the medians. Python standard library only.
Usage: preview_latency.py WSD SCENE [EDITS]
"""
import json
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request

wsd, scene_path = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
edits = int(sys.argv[3]) if len(sys.argv) > 3 else 5

work = tempfile.mkdtemp(prefix="wsd-preview-bench-")
source_dir = os.path.dirname(scene_path)
for entry in os.listdir(source_dir):  # the scene with what it names beside it (textures, includes)
    src = os.path.join(source_dir, entry)
    (shutil.copytree if os.path.isdir(src) else shutil.copy)(src, os.path.join(work, entry))
scene = os.path.join(work, os.path.basename(scene_path))
text = open(scene).read()
colour = re.search(r"color <([^>]*)>", text)
if not colour:
    sys.exit("preview_latency: no `color <...>` to edit in " + scene_path)

server = subprocess.Popen([wsd, "preview", scene, "--port", "0"], stdout=subprocess.PIPE,
                          stderr=subprocess.DEVNULL, text=True)
opener = urllib.request.build_opener(urllib.request.ProxyHandler({}))
try:
    url = re.search(r"http://[^ ]+/", server.stdout.readline()).group(0)
    events = opener.open(url + "events", timeout=600)

    def next_snapshot():
        while True:
            line = events.readline()
            if not line:
                sys.exit("preview_latency: the event stream ended")
            if line.startswith(b"data:"):
                return json.loads(line[5:])

    snap = next_snapshot()
    while not (snap["image_id"] > 0 or snap["phase"] == "error"):  # the first image
        snap = next_snapshot()
    if snap["phase"] == "error":
        sys.exit("preview_latency: the scene has errors:\n" + snap["diagnostics"])
    print("%s: %dx%d in %d stages; each edit is saved while the previous render refines"
          % (os.path.basename(scene_path), snap["width"], snap["height"], snap["stages"]))
    noticed, first = [], []
    for i in range(edits):
        generation = snap["generation"]
        edited = text.replace(colour.group(0), "color <%s>" % ("0.5, 0.5, 0.5" if i % 2 == 0 else colour.group(1)), 1)
        start = time.monotonic()
        with open(scene, "w") as f:
            f.write(edited)
        seen = None
        while True:
            snap = next_snapshot()
            if seen is None and snap["generation"] > generation:
                seen = time.monotonic() - start
            if snap["phase"] == "error":
                sys.exit("preview_latency: the edit broke the scene:\n" + snap["diagnostics"])
            if snap["image_generation"] > generation:
                png = opener.open(url + "image?id=%d" % snap["image_id"], timeout=60).read()
                took = time.monotonic() - start
                break
        noticed.append(seen)
        first.append(took)
        print("edit %d: noticed after %.3f s; first new image (stage %d/%d, %dx%d, %d bytes) after %.3f s"
              % (i + 1, seen, snap["stage"], snap["stages"], snap["image_width"], snap["image_height"],
                 len(png), took))
    print("median: noticed %.3f s, first new image %.3f s (range %.3f-%.3f s) over %d edits"
          % (statistics.median(noticed), statistics.median(first), min(first), max(first), edits))
finally:
    server.send_signal(signal.SIGINT)
    try:
        server.wait(30)
    except subprocess.TimeoutExpired:
        server.kill()
    shutil.rmtree(work, ignore_errors=True)
