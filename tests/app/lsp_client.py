# A scripted Language Server Protocol client for `wsd lsp`: starts the server on a pipe, writes
# framed JSON-RPC messages and reads the replies (with a timeout, so that a server that hangs
# fails the test instead of stalling it).
import json
import os
import select
import subprocess
import time


class Client:
    def __init__(self, wsd, cwd=None):
        self.proc = subprocess.Popen([wsd, "lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, cwd=cwd)
        self.buffer = b""
        self.next_id = 1
        self.notifications = []

    def write_raw(self, data):
        self.proc.stdin.write(data)
        self.proc.stdin.flush()

    def send(self, message):
        body = json.dumps(message).encode()
        self.write_raw(b"Content-Length: %d\r\n\r\n" % len(body) + body)

    def notify(self, method, params):
        self.send({"jsonrpc": "2.0", "method": method, "params": params})

    def request(self, method, params, timeout=60):
        rid = self.next_id
        self.next_id += 1
        self.send({"jsonrpc": "2.0", "id": rid, "method": method, "params": params})
        return self.wait_response(rid, timeout)

    def wait_response(self, rid, timeout=60):
        while True:
            m = self.read(timeout)
            if "id" in m and "method" not in m and m["id"] == rid:
                return m
            if "id" not in m:
                self.notifications.append(m)

    def wait_diagnostics(self, uri, version=None, timeout=60):
        """The next publishDiagnostics for `uri` (of `version`, when given: others are dropped)."""
        while True:
            for i, n in enumerate(self.notifications):
                if n.get("method") == "textDocument/publishDiagnostics" and n["params"]["uri"] == uri:
                    del self.notifications[i]
                    if version is None or n["params"].get("version") == version:
                        return n["params"]
                    break
            else:
                m = self.read(timeout)
                if "id" not in m:
                    self.notifications.append(m)

    def _fill(self, deadline):
        left = deadline - time.monotonic()
        if left <= 0:
            raise TimeoutError("no reply from wsd lsp")
        ready, _, _ = select.select([self.proc.stdout], [], [], left)
        if not ready:
            raise TimeoutError("no reply from wsd lsp")
        chunk = os.read(self.proc.stdout.fileno(), 1 << 20)
        if not chunk:
            raise EOFError("wsd lsp closed its output (exit status %s)" % self.proc.poll())
        self.buffer += chunk

    def read(self, timeout=60):
        deadline = time.monotonic() + timeout
        while b"\r\n\r\n" not in self.buffer:
            self._fill(deadline)
        header, rest = self.buffer.split(b"\r\n\r\n", 1)
        length = None
        for line in header.split(b"\r\n"):
            name, _, value = line.partition(b":")
            if name.strip().lower() == b"content-length":
                length = int(value)
        assert length is not None, "reply without Content-Length: %r" % header
        self.buffer = rest
        while len(self.buffer) < length:
            self._fill(deadline)
        body, self.buffer = self.buffer[:length], self.buffer[length:]
        return json.loads(body)

    def initialize(self, encodings=None):
        caps = {"general": {"positionEncodings": encodings}} if encodings else {}
        r = self.request("initialize", {"processId": None, "rootUri": None, "capabilities": caps})
        self.notify("initialized", {})
        return r

    def close(self):
        r = self.request("shutdown", None)
        assert r.get("result", 1) is None, r
        self.notify("exit", None)
        self.proc.stdin.close()
        return self.proc.wait(timeout=30)
