# `wsd lsp` driven by a scripted client over a pipe (usage: lsp_test.py WSD). Each check prints
# what failed; the exit status is the number of failures (0: all passed).
import json
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lsp_client import Client  # noqa: E402

WSD = sys.argv[1]
failures = 0


def check(condition, what, detail=""):
    global failures
    if not condition:
        failures += 1
        print("FAIL: %s %s" % (what, detail))
    else:
        print("ok: %s" % what)


def uri_of(path):
    return "file://" + os.path.abspath(path)


def position(text, needle, nth=0, delta=0):
    """The LSP position (UTF-16) of the nth occurrence of `needle` in `text`, moved by delta characters."""
    at = -1
    for _ in range(nth + 1):
        at = text.index(needle, at + 1)
    at += delta
    line = text.count("\n", 0, at)
    start = text.rfind("\n", 0, at) + 1
    return {"line": line, "character": len(text[start:at].encode("utf-16-le")) // 2}


INCLUDE = """// shared names
let R = 2
fn twice(x) { return x * 2 }
"""
HEADER = """camera { position <0, 0, -5>  look_at <0, 0, 0>  fov 60 }
light point { position <0, 5, -5> }
include "inc.wsdi"
let shiny = material { color <1, 0.5, 0>  specular 0.5 }
"""
BROKEN = HEADER + "sphere { center <0, 0, 0>  radius -1  material shiny }\n"
FIXED = HEADER + "sphere { center <0, 0, 0>  radius twice(R)  material shiny }\n"

with tempfile.TemporaryDirectory() as tmp:
    with open(os.path.join(tmp, "inc.wsdi"), "w") as f:
        f.write(INCLUDE)
    main = os.path.join(tmp, "main.wsd")
    uri = uri_of(main)
    c = Client(WSD, cwd=tmp)

    r = c.initialize()
    caps = r.get("result", {}).get("capabilities", {})
    check(caps.get("positionEncoding") == "utf-16", "initialize: utf-16 positions", r)
    check(caps.get("textDocumentSync", {}).get("change") == 1 and caps.get("hoverProvider"),
          "initialize: full sync and hover", caps)
    r = c.request("initialize", {"processId": None, "capabilities": {"general": {"positionEncodings": ["utf-32"]}}})
    check(r.get("error", {}).get("code") == -32600, "initialize may be sent once only", r)

    # An error, with its range: the value -1 of radius.
    c.notify("textDocument/didOpen",
             {"textDocument": {"uri": uri, "languageId": "wsd", "version": 1, "text": BROKEN}})
    d = c.wait_diagnostics(uri)["diagnostics"]
    start = position(BROKEN, "-1")
    end = position(BROKEN, "-1", delta=2)
    check(len(d) == 1 and d[0]["severity"] == 1 and "radius" in d[0]["message"]
          and d[0]["range"] == {"start": start, "end": end}, "an error with its range", d)

    # Fixed by didChange: an empty list.
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 2},
                                        "contentChanges": [{"text": FIXED}]})
    p = c.wait_diagnostics(uri, 2)
    check(p["diagnostics"] == [] and p.get("version") == 2, "fixed by didChange: no diagnostics", p)

    # Hover on a property: its type, range, default and meaning from the tables.
    h = c.request("textDocument/hover", {"textDocument": {"uri": uri}, "position": position(FIXED, "radius", delta=2)})
    text = h.get("result", {}).get("contents", {}).get("value", "") if h.get("result") else ""
    check("radius" in text and "a number" in text and "> 0" in text and "Default: required" in text,
          "hover on radius", h)
    # Hover on a name: where it is defined and its type.
    h = c.request("textDocument/hover", {"textDocument": {"uri": uri}, "position": position(FIXED, "shiny", nth=1)})
    text = h.get("result", {}).get("contents", {}).get("value", "") if h.get("result") else ""
    check("material" in text and "main.wsd:4:5" in text, "hover on a let name", h)
    h = c.request("textDocument/hover", {"textDocument": {"uri": uri}, "position": position(FIXED, "R)")})
    text = h.get("result", {}).get("contents", {}).get("value", "") if h.get("result") else ""
    check("number" in text and "inc.wsdi:2:5" in text, "hover on a name from an include", h)
    # A type known only by evaluating the scene, with the next request already sent (pipelined).
    typed = FIXED + "let v = twice(R)\n"
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 3}, "contentChanges": [{"text": typed}]})
    hover_v = {"textDocument": {"uri": uri}, "position": position(typed, "v =")}
    c.write_raw(b"".join(b"Content-Length: %d\r\n\r\n" % len(m) + m for m in (
        json.dumps({"jsonrpc": "2.0", "id": 700, "method": "textDocument/hover", "params": hover_v}).encode(),
        json.dumps({"jsonrpc": "2.0", "id": 701, "method": "textDocument/documentSymbol",
                    "params": {"textDocument": {"uri": uri}}}).encode())))
    h = c.wait_response(700)
    check("Type: number" in json.dumps(h), "hover with the next request pipelined: the evaluated type", h)
    c.wait_response(701)
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 3}, "contentChanges": [{"text": FIXED}]})

    # Completion in a sphere: its properties, not the camera's.
    edited = FIXED.replace("material shiny }", "material shiny\n  ra }")
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 3},
                                        "contentChanges": [{"text": edited}]})
    r = c.request("textDocument/completion", {"textDocument": {"uri": uri}, "position": position(edited, "  ra", delta=4)})
    labels = [i["label"] for i in (r.get("result") or [])]
    check("radius" in labels and "center" in labels and "translate" in labels and "fov" not in labels,
          "completion in a sphere", labels)
    # In value position: the names in scope.
    r = c.request("textDocument/completion", {"textDocument": {"uri": uri},
                                              "position": position(edited, "material shiny", delta=14)})
    labels = [i["label"] for i in (r.get("result") or [])]
    check("shiny" in labels and "R" in labels and "twice" in labels and "radius" not in labels,
          "completion of a value", labels)
    # A comment before the word says nothing of what comes next: a block comment's '/', a line
    # comment that ends in ','.
    for i, before in enumerate(["material shiny /* x */ ", "material shiny // x, y,\n  "]):
        commented = FIXED.replace("material shiny }", before + "ra }")
        c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 4 + i},
                                            "contentChanges": [{"text": commented}]})
        r = c.request("textDocument/completion",
                      {"textDocument": {"uri": uri}, "position": position(commented, "ra }", delta=2)})
        labels = [x["label"] for x in (r.get("result") or [])]
        check("radius" in labels and "shiny" not in labels, "completion after a comment: " + before.strip(), labels)
    # Inside a comment or a string there is nothing to complete.
    prose = FIXED + '// the sh\nlet label = "the sh" /* the sh */\n'
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 6},
                                        "contentChanges": [{"text": prose}]})
    for at in (position(prose, "the sh", delta=6), position(prose, "the sh", nth=1, delta=6),
               position(prose, "the sh", nth=2, delta=6)):
        r = c.request("textDocument/completion", {"textDocument": {"uri": uri}, "position": at})
        check(r.get("result") == [], "no completion in a comment or string at %s" % at, r)
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 6},
                                        "contentChanges": [{"text": edited}]})
    # At statement level: keywords and names.
    r = c.request("textDocument/completion", {"textDocument": {"uri": uri}, "position": {"line": 4, "character": 0}})
    labels = [i["label"] for i in (r.get("result") or [])]
    check("sphere" in labels and "let" in labels and "shiny" in labels and "radius" not in labels,
          "completion at statement level", labels)
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 7},
                                        "contentChanges": [{"text": FIXED}]})

    # Definition of a let across an include, and of the include string.
    r = c.request("textDocument/definition", {"textDocument": {"uri": uri}, "position": position(FIXED, "R)")})
    res = r.get("result") or {}
    check(res.get("uri") == uri_of(os.path.join(tmp, "inc.wsdi"))
          and res.get("range", {}).get("start") == {"line": 1, "character": 4}, "definition across an include", r)
    r = c.request("textDocument/definition", {"textDocument": {"uri": uri}, "position": position(FIXED, "inc.wsdi")})
    res = r.get("result") or {}
    check(res.get("uri") == uri_of(os.path.join(tmp, "inc.wsdi")), "definition of an include string", r)
    r = c.request("textDocument/definition", {"textDocument": {"uri": uri}, "position": position(FIXED, "shiny", nth=1)})
    res = r.get("result") or {}
    check(res.get("uri") == uri and res.get("range", {}).get("start") == {"line": 3, "character": 4},
          "definition in the document", r)

    # Document symbols.
    r = c.request("textDocument/documentSymbol", {"textDocument": {"uri": uri}})
    names = [s["name"] for s in (r.get("result") or [])]
    check(names == ["camera", "light point", "shiny", "sphere"], "document symbols", names)

    # Formatting is answered (a list of edits).
    r = c.request("textDocument/formatting", {"textDocument": {"uri": uri}, "options": {"tabSize": 4, "insertSpaces": True}})
    check(isinstance(r.get("result"), list), "formatting answered", r)

    # An error in an included file shows at the include line, with the chain.
    with open(os.path.join(tmp, "bad.wsdi"), "w") as f:
        f.write("let broken = 1 +\n")
    inc_text = HEADER + 'include "bad.wsdi"\n'
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 8},
                                        "contentChanges": [{"text": inc_text}]})
    d = c.wait_diagnostics(uri, 8)["diagnostics"]
    check(len(d) >= 1 and d[0]["range"]["start"] == position(inc_text, '"bad.wsdi"')
          and "bad.wsdi:" in d[0]["message"] and "included from" in d[0]["message"],
          "an included file's error at the include line", d)

    # Garbage bytes, a bad header, broken JSON, unknown methods and wrong params: errors, not an exit.
    c.write_raw(b"\x00\xff\xfe garbage \r\n\r\n")
    c.write_raw(b"Content-Length: abc\r\n\r\n")
    c.send({"jsonrpc": "2.0", "id": 900, "method": "no/such/method"})
    r = c.wait_response(900)
    check(r.get("error", {}).get("code") == -32601, "unknown method", r)
    c.send({"jsonrpc": "2.0", "id": 901, "method": "textDocument/hover", "params": {"position": 3}})
    r = c.wait_response(901)
    check(r.get("error", {}).get("code") == -32602, "wrong params", r)
    # A position outside LSP's uinteger range is invalid params, not wrapped or truncated to another one.
    for bad in ({"line": -1, "character": 0}, {"line": 0, "character": 1.5}, {"line": 4294967296, "character": 0}):
        r = c.request("textDocument/hover", {"textDocument": {"uri": uri}, "position": bad})
        check(r.get("error", {}).get("code") == -32602, "an invalid position %s" % bad, r)
    body = b'{"jsonrpc": "2.0", "id": 902, "method": '
    c.write_raw(b"Content-Length: %d\r\n\r\n" % len(body) + body)
    r = c.read()
    check(r.get("error", {}).get("code") == -32700, "broken JSON", r)
    # A half message: its announced length swallows what follows, and the server reads on.
    c.write_raw(b"Content-Length: 60\r\n\r\n{\"jsonrpc\": \"2.0\", \"id\": 903,")
    c.write_raw(b"\r\n" * 20)
    r = c.read()
    check(r.get("error", {}).get("code") == -32700, "a half message", r)
    r = c.request("textDocument/documentSymbol", {"textDocument": {"uri": uri}})
    check(isinstance(r.get("result"), list), "still answering after garbage", r)

    # A scene that loops forever is stopped by the language's limits; the server goes on.
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 9},
                                        "contentChanges": [{"text": "fn f(n) { return f(n + 1) }\nlet x = f(0)\n"}]})
    d = c.wait_diagnostics(uri, 9)["diagnostics"]
    check(len(d) >= 1 and d[0]["severity"] == 1, "a runaway recursion is an error", d)

    # A scene that runs for minutes within the language's limits gives way to messages: its check,
    # and hover's evaluation of the scene, stop for them, and the server answers at once.
    slow = ("camera { position <0, 0, -5>  look_at <0, 0, 0> }\nlet k = 3\n"
            "for i in 0..100000000 { let a = [" + ", ".join(["i"] * 200) + "] }\n")
    c.notify("textDocument/didChange", {"textDocument": {"uri": uri, "version": 10},
                                        "contentChanges": [{"text": slow}]})
    time.sleep(0.5)  # the check is under way
    for method, extra in (("textDocument/documentSymbol", {}),
                          ("textDocument/hover", {"position": {"line": 1, "character": 4}})):
        try:
            r = c.request(method, dict({"textDocument": {"uri": uri}}, **extra), timeout=30)
        except TimeoutError as e:
            r = e
        check(isinstance(r, dict) and r.get("result"), method + " answered during a long check", r)
    # Nor does it hold up another document's diagnostics (queued after it, and its URI sorting after).
    quick_uri = uri_of(os.path.join(tmp, "quick.wsd"))
    c.notify("textDocument/didOpen", {"textDocument": {"uri": quick_uri, "languageId": "wsd", "version": 1,
                                                       "text": "let q = nope\n"}})
    try:
        d = c.wait_diagnostics(quick_uri, 1, timeout=30)["diagnostics"]
    except TimeoutError as e:
        d = e
    check(isinstance(d, list) and any("nope" in x["message"] for x in d),
          "another document's diagnostics during a long check", d)

    status = c.close()
    check(status == 0, "exit after shutdown: status 0", status)

    # UTF-16 and UTF-32 columns after a non-ASCII string on the error's line.
    scene = 'let s = "é😀"  let t = nope\n'
    for enc, width in (("utf-16", 3), ("utf-32", 2)):
        c = Client(WSD, cwd=tmp)
        r = c.initialize(["utf-8", enc] if enc == "utf-32" else None)
        check(r["result"]["capabilities"]["positionEncoding"] == enc, "encoding " + enc, r)
        c.notify("textDocument/didOpen",
                 {"textDocument": {"uri": uri_of(os.path.join(tmp, "u.wsdi")), "languageId": "wsd", "version": 1,
                                   "text": scene}})
        d = c.wait_diagnostics(uri_of(os.path.join(tmp, "u.wsdi")))["diagnostics"]
        col = len('let s = "') + width + len('"  let t = ')
        check(len(d) == 1 and d[0]["range"]["start"] == {"line": 0, "character": col}
              and d[0]["range"]["end"] == {"line": 0, "character": col + 4}, "columns in " + enc, d)
        check(c.close() == 0, "exit status after " + enc)

    # A change with a range (sent although full sync is asked for) edits that range.
    c = Client(WSD, cwd=tmp)
    c.initialize()
    e_uri = uri_of(os.path.join(tmp, "e.wsdi"))
    before = 'let s = "😀"  let b = 1\n'
    c.notify("textDocument/didOpen", {"textDocument": {"uri": e_uri, "languageId": "wsd", "version": 1, "text": before}})
    c.wait_diagnostics(e_uri, 1)
    one = position(before, "1")
    c.notify("textDocument/didChange", {"textDocument": {"uri": e_uri, "version": 2}, "contentChanges": [
        {"range": {"start": one, "end": dict(one, character=one["character"] + 1)}, "text": "nope"}]})
    d = c.wait_diagnostics(e_uri, 2)["diagnostics"]
    check(len(d) == 1 and d[0]["message"] == "unknown name 'nope'"
          and d[0]["range"] == {"start": one, "end": dict(one, character=one["character"] + 4)},
          "a ranged change edits its range", d)
    c.close()

    # A scene on one long line, with astral characters along it: positions stay right, and
    # converting them does not rescan the line each time (20000 symbols took minutes).
    for enc in ("utf-16", "utf-32"):
        c = Client(WSD, cwd=tmp)
        c.initialize([enc] if enc == "utf-32" else None)
        l_uri = uri_of(os.path.join(tmp, "line.wsdi"))
        parts = ['let a%d = "é😀" ' % i for i in range(20000)]
        line = "".join(parts) + "\n"
        c.notify("textDocument/didOpen", {"textDocument": {"uri": l_uri, "languageId": "wsd", "version": 1, "text": line}})
        width = (lambda t: len(t.encode("utf-16-le")) // 2) if enc == "utf-16" else len
        try:
            r = c.request("textDocument/documentSymbol", {"textDocument": {"uri": l_uri}}, timeout=60)
            got = [(x["name"], x["selectionRange"]["start"]) for x in r["result"]]
            starts = [0]
            for part in parts:
                starts.append(starts[-1] + width(part))
            want = [("a%d" % i, {"line": 0, "character": starts[i] + 4}) for i in range(20000)]
            check(got == want, "symbols along a long line in " + enc, [g for g, w in zip(got, want) if g != w][:3])
            at = {"line": 0, "character": starts[19999] + 5}
            h = c.request("textDocument/hover", {"textDocument": {"uri": l_uri}, "position": at}, timeout=60)
            check(h["result"] and h["result"]["range"]["start"] == dict(at, character=at["character"] - 1),
                  "hover at the end of a long line in " + enc, h)
        except TimeoutError as e:
            check(False, "symbols along a long line in " + enc, e)
        c.close()

    # An include of a device or a pipe is refused, not read: /dev/zero never ends, and /dev/stdin
    # is the server's own input.
    for device in ("/dev/zero", "/dev/stdin"):
        c = Client(WSD, cwd=tmp)
        c.initialize()
        z_uri = uri_of(os.path.join(tmp, "z.wsdi"))
        c.notify("textDocument/didOpen", {"textDocument": {"uri": z_uri, "languageId": "wsd", "version": 1,
                                                           "text": 'include "%s"\nlet y = 1\n' % device}})
        try:
            d = c.wait_diagnostics(z_uri, 1, timeout=20)["diagnostics"]
            check(len(d) == 1 and "not a regular file" in d[0]["message"], "include " + device + ": refused", d)
            for method in ("textDocument/completion", "textDocument/hover"):
                r = c.request(method, {"textDocument": {"uri": z_uri}, "position": {"line": 1, "character": 4}},
                              timeout=20)
                check("result" in r, "include " + device + ": " + method + " answered", r)
            check(c.close() == 0, "include " + device + ": exit status 0")
        except (TimeoutError, EOFError) as e:
            check(False, "include " + device + " answered", e)
            c.proc.kill()

    # Nor is a mesh file naming the server's own input or output: the scene reads /dev/null there.
    for device in ("/dev/stdin", "/dev/stdout"):
        c = Client(WSD, cwd=tmp)
        c.initialize()
        m_uri = uri_of(os.path.join(tmp, "mesh.wsd"))
        c.notify("textDocument/didOpen", {"textDocument": {"uri": m_uri, "languageId": "wsd", "version": 1, "text":
                 'camera { position <0, 0, -5>  look_at <0, 0, 0> }\nmesh { file "%s"  material { color <1, 1, 1> } }\n'
                 % device}})
        try:
            d = c.wait_diagnostics(m_uri, 1, timeout=20)["diagnostics"]
            check(any("not a regular file" in x["message"] for x in d), "mesh " + device + ": refused", d)
            r = c.request("textDocument/documentSymbol", {"textDocument": {"uri": m_uri}}, timeout=20)
            check(isinstance(r.get("result"), list), "mesh " + device + ": still answering", r)
            check(c.close() == 0, "mesh " + device + ": exit status 0")
        except (TimeoutError, EOFError, ValueError) as e:
            check(False, "mesh " + device + " answered", e)
            c.proc.kill()

    # An included file's unsaved text is what the including document is checked with.
    c = Client(WSD, cwd=tmp)
    c.initialize()
    c.notify("textDocument/didOpen", {"textDocument": {"uri": uri, "languageId": "wsd", "version": 1, "text": FIXED}})
    check(c.wait_diagnostics(uri, 1)["diagnostics"] == [], "open: no diagnostics")
    inc_uri = uri_of(os.path.join(tmp, "inc.wsdi"))
    c.notify("textDocument/didOpen", {"textDocument": {"uri": inc_uri, "languageId": "wsd", "version": 1,
                                                       "text": "let Q = 2\n"}})
    d = c.wait_diagnostics(uri)["diagnostics"]
    check(len(d) == 1 and "twice" in d[0]["message"], "an open include's unsaved text is used", d)
    c.close()

    # Closing the included document: the includer is checked again, with the file on disk.
    c = Client(WSD, cwd=tmp)
    c.initialize()
    with open(os.path.join(tmp, "lib.wsdi"), "w") as f:
        f.write("let L = 1\n")
    main_uri, lib_uri = uri_of(os.path.join(tmp, "m2.wsd")), uri_of(os.path.join(tmp, "lib.wsdi"))
    c.notify("textDocument/didOpen", {"textDocument": {"uri": main_uri, "languageId": "wsd", "version": 1,
              "text": "camera { position <0,0,-5> look_at <0,0,0> }\ninclude \"lib.wsdi\"\nlet y = L\n"}})
    c.wait_diagnostics(main_uri, 1)
    c.notify("textDocument/didOpen", {"textDocument": {"uri": lib_uri, "languageId": "wsd", "version": 1,
                                                       "text": "let M = 1\n"}})
    d = c.wait_diagnostics(main_uri)["diagnostics"]
    check(any("unknown name 'L'" in x["message"] for x in d), "an open include's text hides L", d)
    c.notify("textDocument/didClose", {"textDocument": {"uri": lib_uri}})
    d = c.wait_diagnostics(main_uri)["diagnostics"]
    check(not any(x["severity"] == 1 for x in d), "closed: the include is read from disk again", d)

    # A file that includes itself three times: hover walks each file once (it was 3^16 walks).
    with open(os.path.join(tmp, "loop.wsdi"), "w") as f:
        f.write('let K = 1\ninclude "loop.wsdi"\ninclude "loop.wsdi"\ninclude "loop.wsdi"\n')
    h_uri = uri_of(os.path.join(tmp, "h.wsd"))
    c.notify("textDocument/didOpen", {"textDocument": {"uri": h_uri, "languageId": "wsd", "version": 1,
                                                       "text": 'include "loop.wsdi"\nlet y = K\n'}})
    c.wait_diagnostics(h_uri, 1)
    r = c.request("textDocument/hover", {"textDocument": {"uri": h_uri}, "position": {"line": 1, "character": 8}},
                  timeout=20)
    check("loop.wsdi:1:5" in r["result"]["contents"]["value"], "hover through a self-including file", r)

    # A note in an untitled document names the document's own URI.
    c.notify("textDocument/didOpen", {"textDocument": {"uri": "untitled:Untitled-1", "languageId": "wsd",
                                                       "version": 1, "text": "let a = 1\nlet a = 2\n"}})
    d = c.wait_diagnostics("untitled:Untitled-1")["diagnostics"]
    uris = [i["location"]["uri"] for x in d for i in x.get("relatedInformation", [])]
    check(uris and all(u == "untitled:Untitled-1" for u in uris), "untitled: related information", uris)

    # Requests after shutdown are refused, initialize included.
    check(c.request("shutdown", None)["result"] is None, "shutdown")
    r = c.request("initialize", {"processId": None, "capabilities": {}})
    check("error" in r and r["error"]["code"] == -32600, "initialize after shutdown is refused", r)
    c.notify("exit", None)
    check(c.proc.wait(timeout=30) == 0, "exit after shutdown: status 0")

    # Exit without shutdown: status 1.
    c = Client(WSD, cwd=tmp)
    c.initialize()
    c.notify("exit", None)
    check(c.proc.wait(timeout=30) == 1, "exit without shutdown: status 1")

sys.exit(min(failures, 100))
