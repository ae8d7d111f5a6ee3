"""`wsd preview` through plain HTTP and its signals, without a browser (usage: preview_http_test.py
WSD [TEST...]). Each test starts its own server on a free port and stops it with SIGINT; every wait
polls with a deadline. The exit status is the number of failed tests."""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

WSD = os.path.abspath(sys.argv[1])

HEAD = """settings {{ width {w}  height {h}{extra} }}
camera {{ position <0, 0, -5>  look_at <0, 0, 0>  up <0, 1, 0>  fov 50 }}
light point {{ position <4, 6, -8> }}
"""
SCENE = HEAD.format(w=64, h=48, extra="") + """sphere { center <0, 0, 0>  radius 1.5  material material { color <1, 0, 0> } }
"""
BLUE = SCENE.replace("<1, 0, 0>", "<0, 0, 1>")
LONG_LOOP = SCENE + "let s = 0\nfor i in 0 .. 99999990 { let s = s + 1 }\n"


class Failure(Exception):
    pass


def check(condition, what):
    if not condition:
        raise Failure(what)


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


class Preview:
    """A running `wsd preview` in `work`; its port is read from the line it prints."""

    def __init__(self, work, scene, *args):
        self.errors = open(os.path.join(work, "stderr.txt"), "w+")
        self.process = subprocess.Popen([WSD, "preview", scene, "--port", "0", "--threads", "2", *args],
                                        cwd=work, stdout=subprocess.PIPE, stderr=self.errors, text=True)
        line = self.process.stdout.readline()
        check("http://127.0.0.1:" in line, "the preview prints its address: " + repr(line))
        self.port = int(line.split("http://127.0.0.1:")[1].split("/")[0])

    def get(self, path, headers=None, timeout=5):
        request = urllib.request.Request("http://127.0.0.1:%d%s" % (self.port, path), headers=headers or {})
        try:
            with urllib.request.urlopen(request, timeout=timeout) as r:
                return r.status, dict(r.headers), r.read()
        except urllib.error.HTTPError as e:
            return e.code, dict(e.headers), e.read()

    def status(self):
        return json.loads(self.get("/status")[2])

    def wait(self, predicate, what, timeout=10):
        deadline = time.monotonic() + timeout
        s = self.status()
        while not predicate(s):
            check(time.monotonic() < deadline, "%s within %g s (last status %s)" % (what, timeout, s))
            time.sleep(0.05)
            s = self.status()
        return s

    def stop(self, within=3):
        """SIGINT; the server must end with status 0 within `within` seconds."""
        start = time.monotonic()
        self.process.send_signal(signal.SIGINT)
        try:
            code = self.process.wait(timeout=within)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
            raise Failure("SIGINT stops the server within %g s" % within)
        check(code == 0, "the server stops with status 0 (got %d)" % code)
        return time.monotonic() - start

    def kill(self):
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()


def done(generation):
    return lambda s: s["generation"] >= generation and s["phase"] == "done"


def test_save_abandons_a_long_evaluation(work):
    scene = os.path.join(work, "s.wsd")
    write(scene, LONG_LOOP)
    p = Preview(work, "s.wsd")
    try:
        p.wait(lambda s: s["phase"] == "loading", "the long load starts")
        time.sleep(0.3)
        write(scene, SCENE)
        p.wait(done(2), "a save during a long evaluation renders the fixed scene", timeout=5)
        write(scene, LONG_LOOP)
        p.wait(lambda s: s["generation"] >= 3 and s["phase"] == "loading", "the long load starts again")
        time.sleep(0.3)
        p.stop()
    finally:
        p.kill()


def test_caustics_show_coarse_at_once_and_stop(work):
    scene = os.path.join(work, "s.wsd")
    write(scene, HEAD.format(w=64, h=48, extra="  caustic_photons 100000000") + """
plane { normal <0, 1, 0>  distance -1.5  material material { color <1, 1, 1> } }
sphere { center <0, 0, 0>  radius 1  material material { color <1, 1, 1>  transmission 1  ior 1.5 } }
""")
    p = Preview(work, "s.wsd")
    try:
        p.wait(lambda s: s["image_id"] > 0, "a coarse image before the big photon map", timeout=5)
        time.sleep(0.5)  # well into the full size's photons
        p.stop()
    finally:
        p.kill()


def raw_request(port, text, timeout=5):
    """Sends `text` on a new connection; the connection and the status line of the answer."""
    conn = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    conn.sendall(text.encode())
    line = b""
    try:
        while not line.endswith(b"\r\n"):
            byte = conn.recv(1)
            if not byte:
                break
            line += byte
    except socket.timeout:
        pass  # no answer: the line so far (empty)
    return conn, line.decode(errors="replace").strip()


def test_slow_and_idle_clients_do_not_delay_the_stop(work):
    write(os.path.join(work, "s.wsd"), SCENE)
    p = Preview(work, "s.wsd")
    idle = slow = None
    stopping = threading.Event()
    try:
        p.wait(done(1), "the first render")
        idle = socket.create_connection(("127.0.0.1", p.port))
        slow = socket.create_connection(("127.0.0.1", p.port))
        slow.sendall(b"GET / HTTP/1.1\r\nHost: wsd\r\n")

        def drip():  # a header line every half second, never the end of the request
            while not stopping.wait(0.5):
                try:
                    slow.sendall(b"X-Slow: 1\r\n")
                except OSError:
                    return

        threading.Thread(target=drip, daemon=True).start()
        time.sleep(1.2)
        p.stop(within=2)
    finally:
        stopping.set()
        for conn in (idle, slow):
            if conn:
                conn.close()
        p.kill()


def test_many_event_streams_leave_the_server_responsive(work):
    write(os.path.join(work, "s.wsd"), SCENE)
    p = Preview(work, "s.wsd")
    streams = []
    try:
        p.wait(done(1), "the first render")
        codes = []
        for i in range(40):
            conn, line = raw_request(p.port, "GET /events HTTP/1.1\r\nHost: wsd\r\n\r\n")
            streams.append(conn)
            check(line != "", "event stream %d is answered (%s before it)" % (i + 1, codes))
            codes.append(line.split(" ")[1] if " " in line else line)
        check(codes.count("200") >= 16, "16 or more event streams are served: %s" % codes)
        check(codes.count("503") >= 1, "too many event streams are answered 503: %s" % codes)
        for path in ("/", "/status", "/image"):
            check(p.get(path, timeout=2)[0] == 200, "GET %s is answered with 40 event streams open" % path)
        p.stop()
    finally:
        for conn in streams:
            conn.close()
        p.kill()


def test_recreated_directories_and_late_includes_are_noticed(work):
    dd = os.path.join(work, "dd")
    os.mkdir(dd)
    write(os.path.join(dd, "s.wsd"), SCENE)
    p = Preview(work, "dd/s.wsd")
    try:
        p.wait(done(1), "the first render")
        shutil.rmtree(dd)
        g = p.wait(lambda s: s["phase"] == "error", "a deleted directory is an error")["generation"]
        os.mkdir(dd)
        write(os.path.join(dd, "s.wsd"), BLUE)
        g = p.wait(lambda s: s["generation"] > g and s["phase"] == "done", "the recreated directory is seen",
                   timeout=5)["generation"]
        # The scene now includes a file in a directory that does not exist yet.
        write(os.path.join(dd, "s.wsd"), 'include "sub/c.wsdi"\n' + BLUE.replace("<0, 0, 1>", "colour"))
        g = p.wait(lambda s: s["generation"] > g and "sub/c.wsdi" in s["diagnostics"],
                   "the missing include is reported", timeout=5)["generation"]
        os.mkdir(os.path.join(dd, "sub"))
        write(os.path.join(dd, "sub", "c.wsdi"), "let colour = <0, 1, 0>\n")
        g = p.wait(lambda s: s["generation"] > g and s["phase"] == "done", "a late include is seen",
                   timeout=5)["generation"]
        shutil.rmtree(os.path.join(dd, "sub"))
        os.mkdir(os.path.join(dd, "sub"))
        write(os.path.join(dd, "sub", "c.wsdi"), "let colour = <1, 1, 0>\n")
        p.wait(lambda s: s["generation"] > g and s["phase"] == "done",
               "the include's recreated directory is seen", timeout=5)
        p.stop()
    finally:
        p.kill()


def test_a_linked_scene_follows_its_target(work):
    os.mkdir(os.path.join(work, "other"))
    target = os.path.join(work, "other", "real.wsd")
    write(target, SCENE)
    os.symlink("other/real.wsd", os.path.join(work, "s.wsd"))
    p = Preview(work, "s.wsd")
    try:
        p.wait(done(1), "the first render")
        write(target, BLUE)
        p.wait(done(2), "saving the link's target renders again", timeout=5)
        p.stop()
    finally:
        p.kill()


def test_a_save_cancels_an_expensive_tile_soon(work):
    scene = os.path.join(work, "s.wsd")
    write(scene, HEAD.format(w=64, h=64, extra="  supersamples 256  indirect_samples 256") + """
plane { normal <0, 0, -1>  distance -3  material material { color <1, 1, 1> } }
sphere { center <0, 0, 0>  radius 1.5  material material { color <1, 0, 0> } }
""")  # a wall behind the sphere: each pixel costs 256 × 256 paths, a tile several seconds
    p = Preview(work, "s.wsd")
    try:
        p.wait(lambda s: s["stage"] == s["stages"] - 1 and s["stages"] > 1, "the coarse stages", timeout=20)
        time.sleep(0.5)  # into the full size's first tiles
        write(scene, SCENE)
        p.wait(done(2), "a save during an expensive tile renders the new scene", timeout=2)
        p.stop()
    finally:
        p.kill()


def test_defines_reach_param(work):
    write(os.path.join(work, "s.wsd"), SCENE.replace("width 64", 'width param("w", 64)'))
    p = Preview(work, "s.wsd", "-D", "w=40")
    try:
        s = p.wait(done(1), "the first render")
        check(s["width"] == 40 and s["diagnostics"] == "", "-D w=40 sets the width: %s" % s)
        p.stop()
    finally:
        p.kill()


def test_range_headers_are_ignored(work):
    write(os.path.join(work, "s.wsd"), SCENE)
    p = Preview(work, "s.wsd")
    conns = []
    try:
        p.wait(done(1), "the first render")
        status, _, png = p.get("/image")
        check(status == 200 and png.startswith(b"\x89PNG"), "the image")
        status, _, body = p.get("/image", {"Range": "bytes=" + ",".join(["0-1000"] * 500)})
        check(status == 200 and body == png, "a multi-range request gets the whole image (%d)" % status)
        conn, line = raw_request(p.port, "GET /events HTTP/1.1\r\nHost: wsd\r\nRange: bytes=0-10\r\n\r\n")
        conns.append(conn)
        check(line == "HTTP/1.1 200 OK", "an event stream with a Range header is 200: " + line)
        start = time.monotonic()
        conn, line = raw_request(p.port, "POST /status HTTP/1.1\r\nHost: wsd\r\n\r\n")
        conns.append(conn)
        check(line.startswith("HTTP/1.1 4") and time.monotonic() - start < 2,
              "a POST without Content-Length is refused soon: %s after %.1f s" % (line, time.monotonic() - start))
        # Other methods on the preview's resources: 405 with the methods allowed; elsewhere 404.
        for method in ("POST", "PUT", "PATCH", "DELETE"):
            for path in ("/", "/status", "/image", "/events"):
                conn, line = raw_request(
                    p.port, "%s %s HTTP/1.1\r\nHost: wsd\r\nContent-Length: 2\r\n\r\n{}" % (method, path))
                rest = b""
                while b"\r\n\r\n" not in rest:
                    chunk = conn.recv(4096)
                    if not chunk:
                        break
                    rest += chunk
                conn.close()
                rest = rest.decode("latin-1")
                check(line == "HTTP/1.1 405 Method Not Allowed" and "Allow: GET, HEAD" in rest,
                      "%s %s is 405 with Allow: %s %r" % (method, path, line, rest[:200]))
            conn, line = raw_request(p.port, "%s /nothing HTTP/1.1\r\nHost: wsd\r\nContent-Length: 0\r\n\r\n" % method)
            conn.close()
            check(line.startswith("HTTP/1.1 404"), "%s /nothing is 404: %s" % (method, line))
        p.stop()
    finally:
        for conn in conns:
            conn.close()
        p.kill()


def main():
    tests = [(name, f) for name, f in sorted(globals().items()) if name.startswith("test_")]
    chosen = sys.argv[2:]
    failures = 0
    for name, f in tests:
        if chosen and name not in chosen:
            continue
        work = tempfile.mkdtemp(prefix="wsd-preview-http-")
        start = time.monotonic()
        try:
            f(work)
            print("ok: %s (%.1f s)" % (name, time.monotonic() - start))
        except (Failure, OSError) as e:
            failures += 1
            print("FAIL: %s: %s" % (name, e))
            try:
                with open(os.path.join(work, "stderr.txt")) as err:
                    sys.stdout.write(err.read())
            except OSError:
                pass
        finally:
            shutil.rmtree(work, ignore_errors=True)
    sys.exit(failures)


if __name__ == "__main__":
    main()
