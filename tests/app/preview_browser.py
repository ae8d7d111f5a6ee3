"""`wsd preview` seen through headless chromium (Selenium + chromedriver).

On a temporary scene whose sphere takes its colour from an included file: the image appears at the
scene's size with a red sphere; saving the include (written in place) turns it green; a broken
save of the scene (written to a new file and renamed over it, as editors do) shows the diagnostic
with file:line:col over the last image; fixing it brings a new image back; SIGINT stops the server
with status 0. Every wait polls the page with a deadline; nothing sleeps for a fixed time.
Usage: preview_browser.py WSD
"""
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.support.ui import WebDriverWait

WIDTH, HEIGHT = 96, 72
SCENE = """settings {{ width {w} height {h} }}
camera {{ position <0, 0, -5>  look_at <0, 0, 0>  up <0, 1, 0>  fov 50 }}
light point {{ position <4, 6, -8> }}
include "colour.wsdi"
sphere {{ center <0, 0, 0>  radius 1.5  material material {{ color sphere_colour }} }}
""".format(w=WIDTH, h=HEIGHT)
BROKEN = SCENE.replace("radius 1.5", "radius 1.5 +")

# Draws the image at its natural size into a canvas and reads one pixel: [r, g, b, a].
PIXEL_JS = """
const img = document.getElementById('image');
const c = document.createElement('canvas');
c.width = img.naturalWidth; c.height = img.naturalHeight;
const g = c.getContext('2d');
g.drawImage(img, 0, 0);
return Array.from(g.getImageData(arguments[0], arguments[1], 1, 1).data);
"""

# The page's state: the last snapshot and which image id is drawn.
STATE_JS = """
const img = document.getElementById('image');
const d = document.getElementById('diagnostics');
const s = window.wsdPreview && window.wsdPreview.snapshot;
return {snapshot: s, loaded: Number(img.dataset.loaded || 0), complete: img.complete,
        natural: [img.naturalWidth, img.naturalHeight],
        diagnostics_shown: !d.hidden, diagnostics: d.textContent};
"""


def fail(message):
    print("FAILED: " + message)
    sys.exit(1)


def write_in_place(path, text):
    with open(path, "w") as f:
        f.write(text)


def write_by_rename(path, text):
    tmp = path + ".tmp~"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def main():
    wsd = os.path.abspath(sys.argv[1])
    work = tempfile.mkdtemp(prefix="wsd-preview-test-")
    scene = os.path.join(work, "scene.wsd")
    colour = os.path.join(work, "colour.wsdi")
    write_in_place(scene, SCENE)
    write_in_place(colour, "let sphere_colour = <1, 0, 0>\n")

    errors = open(os.path.join(work, "stderr.txt"), "w+")
    server = subprocess.Popen([wsd, "preview", "scene.wsd", "--port", "0", "--threads", "2"], cwd=work,
                              stdout=subprocess.PIPE, stderr=errors, text=True)

    def server_errors():
        errors.seek(0)
        return errors.read()

    # The first line names the URL; a reader thread keeps the pipe from blocking the server.
    lines = []
    got_line = threading.Event()

    def read_stdout():
        for line in server.stdout:
            lines.append(line)
            got_line.set()

    threading.Thread(target=read_stdout, daemon=True).start()
    driver = None
    try:
        if not got_line.wait(15):
            fail("wsd preview printed no URL; stderr: " + server_errors())
        match = re.search(r"http://127\.0\.0\.1:(\d+)/", lines[0])
        if not match:
            fail("unexpected first line: " + lines[0])
        url = match.group(0)

        options = webdriver.ChromeOptions()
        options.binary_location = "/usr/bin/chromium" if os.path.exists("/usr/bin/chromium") else "chromium"
        for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu",
                    "--no-proxy-server", "--window-size=800,600"):
            options.add_argument(arg)
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver" if os.path.exists("/usr/bin/chromedriver")
                                                  else "chromedriver"), options=options)
        driver.get(url)

        def state():
            return driver.execute_script(STATE_JS)

        def wait_for(what, predicate, timeout=20):
            try:
                return WebDriverWait(driver, timeout, poll_frequency=0.05).until(lambda d: predicate(state()))
            except Exception:
                fail("timed out waiting for " + what + "; page state: " + repr(state()))

        def image_done(after_generation):
            # The full-size image of a generation after `after_generation` is drawn in the page.
            def check(s):
                snap = s["snapshot"]
                return (snap is not None and snap["phase"] == "done" and snap["image_generation"] > after_generation
                        and snap["stage"] == snap["stages"] and s["loaded"] == snap["image_id"] and s["complete"]
                        and s["natural"] == [WIDTH, HEIGHT] and not s["diagnostics_shown"]) and snap
            return check

        def centre():
            return driver.execute_script(PIXEL_JS, WIDTH // 2, HEIGHT // 2)

        # 1. The image appears, at the scene's size, with the red sphere in the middle.
        snap = wait_for("the first image", image_done(0))
        r, g, b, _ = centre()
        if not (r > 120 and g < 60 and b < 60):
            fail("expected a red centre, got %r" % ([r, g, b],))
        if not any(f.endswith("colour.wsdi") for f in snap["files"]):
            fail("the included file is not watched: %r" % snap["files"])
        print("image shown: %dx%d, centre %r" % (WIDTH, HEIGHT, [r, g, b]))

        # 2. Saving the included file (in place) re-renders: the centre turns green.
        generation = snap["generation"]
        write_in_place(colour, "let sphere_colour = <0, 1, 0>\n")
        snap = wait_for("the image after editing the include", image_done(generation))
        r, g, b, _ = centre()
        if not (g > 120 and r < 60 and b < 60):
            fail("expected a green centre after the edit, got %r" % ([r, g, b],))
        print("include edited: generation %d, centre %r" % (snap["generation"], [r, g, b]))

        # 3. A broken save (by rename): the diagnostic, with file:line:col, over the last image.
        generation = snap["generation"]
        write_by_rename(scene, BROKEN)
        s = wait_for("the diagnostics", 
                     lambda s: s if s["diagnostics_shown"] and s["snapshot"]["generation"] > generation else None)
        if not re.search(r"scene\.wsd:5:\d+: error: ", s["diagnostics"]):
            fail("the diagnostics lack file:line:col: " + s["diagnostics"])
        if s["natural"] != [WIDTH, HEIGHT] or centre()[1] < 120:
            fail("the last good image is not kept under the diagnostics: %r" % s)
        print("broken save shows: " + s["diagnostics"].splitlines()[0])

        # 4. Fixing it brings a new image back and hides the diagnostics.
        generation = s["snapshot"]["generation"]
        write_by_rename(scene, SCENE.replace("radius 1.5", "radius 2"))
        snap = wait_for("the image after the fix", image_done(generation))
        r, g, b, _ = centre()
        if not (g > 120 and r < 60):
            fail("expected the green sphere back, got %r" % ([r, g, b],))
        print("fixed: generation %d, image back" % snap["generation"])
    finally:
        if driver is not None:
            driver.quit()
        if server.poll() is None:
            server.send_signal(signal.SIGINT)
        try:
            status = server.wait(10)
        except subprocess.TimeoutExpired:
            server.kill()
            fail("wsd preview did not stop within 10 s of SIGINT")
        stderr = server_errors()
        errors.close()
        subprocess.run(["rm", "-rf", work])
    if status != 0:
        fail("wsd preview exited with %d after SIGINT; stderr: %s" % (status, stderr))
    print("stopped cleanly on SIGINT")


if __name__ == "__main__":
    main()
