#!/usr/bin/env python3
"""The published web player (docs/publish.md) in real headless Chromium.

Bakes a short walk, publishes it, serves the folder over HTTP, loads the page
in Chromium (WebGL 2 on SwiftShader) driven over the DevTools protocol, draws
every frame of the path through the page's test hook and compares it with the
native `walk --keyframes DB --mode hybrid --no-render-holes --save-frames`
frame (PSNR >= 40 dB on RGB); no console errors. Then damaged files: each
must show a message naming the file and what was expected, and draw nothing.

Python standard library only (the DevTools WebSocket client is below).
Chromium needs no --disable-gpu here (WebGL 2 on SwiftShader works with or
without it); as root it needs --no-sandbox.

Usage: web_player.py HYBRIDWALK SOURCE_DIR [--scene S] [--path FILE] [--frames N]
       [--size WxH] [--keep DIR] [--screenshot PNG] [--timing JSON] [--no-tamper]
"""
import argparse
import base64
import functools
import http.server
import json
import math
import os
import re
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request
import zlib

MIN_PSNR_DB = 40.0
failures = []


def check(name, ok, detail=""):
    print(("ok   " if ok else "FAIL ") + name + (f"  ({detail})" if detail else ""), flush=True)
    if not ok:
        failures.append(name)


# ---- PNG (stb's output: 8-bit RGB/RGBA, not interlaced) ------------------

def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or ctype not in (2, 6) or interlace:
                raise ValueError(f"{path}: only 8-bit RGB/RGBA non-interlaced PNGs are read here")
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * bpp
    out = bytearray(h * w * 3)
    prev = bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + ((a + b) >> 1)) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        for x in range(w):
            out[(y * w + x) * 3:(y * w + x) * 3 + 3] = line[x * bpp:x * bpp + 3]
        prev = line
    return w, h, bytes(out)


def write_png(path, w, h, rgb):
    raw = b"".join(b"\x00" + rgb[y * w * 3:(y + 1) * w * 3] for y in range(h))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def hw32(data):
    """docs/publish.md "Checksum: hw32"."""
    h = 2166136261
    padded = data + b"\0" * (-len(data) % 4)
    for (w,) in struct.iter_unpack("<I", padded):
        h = ((h ^ w) * 16777619) & 0xFFFFFFFF
    return h ^ (len(data) & 0xFFFFFFFF)


def psnr(a, b):
    se = sum((x - y) * (x - y) for x, y in zip(a, b))
    if se == 0:
        return math.inf
    return 10 * math.log10(255 * 255 / (se / len(a)))


def rgba_to_rgb(rgba):
    out = bytearray(len(rgba) // 4 * 3)
    out[0::3], out[1::3], out[2::3] = rgba[0::4], rgba[1::4], rgba[2::4]
    return bytes(out)


# ---- a minimal WebSocket client and the DevTools protocol -----------------

class WebSocket:
    def __init__(self, url):
        assert url.startswith("ws://")
        hostport, path = url[5:].split("/", 1)
        host, port = hostport.split(":")
        self.sock = socket.create_connection((host, int(port)), timeout=120)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET /{path} HTTP/1.1\r\nHost: {hostport}\r\nUpgrade: websocket\r\n"
                           f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                           "Sec-WebSocket-Version: 13\r\n\r\n").encode())
        head = b""
        while b"\r\n\r\n" not in head:
            more = self.sock.recv(1)
            if not more:
                raise ConnectionError("DevTools closed the WebSocket handshake")
            head += more
        if b" 101 " not in head.split(b"\r\n")[0]:
            raise ConnectionError(f"DevTools WebSocket handshake: {head[:200]!r}")

    def _read(self, n):
        buf = b""
        while len(buf) < n:
            more = self.sock.recv(n - len(buf))
            if not more:
                raise ConnectionError("DevTools WebSocket closed")
            buf += more
        return buf

    def send(self, text):
        payload = text.encode()
        n = len(payload)
        head = b"\x81" + (bytes([0x80 | n]) if n < 126 else
                          b"\xfe" + struct.pack(">H", n) if n < 65536 else b"\xff" + struct.pack(">Q", n))
        mask = os.urandom(4)
        self.sock.sendall(head + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))

    def recv(self):
        message = b""
        while True:
            b0, b1 = self._read(2)
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack(">H", self._read(2))[0]
            elif n == 127:
                n = struct.unpack(">Q", self._read(8))[0]
            payload = self._read(n)
            op = b0 & 0x0F
            if op == 8:
                raise ConnectionError("DevTools closed the WebSocket")
            if op == 9:  # ping
                continue
            message += payload
            if b0 & 0x80:
                return message.decode()


class DevTools:
    def __init__(self, ws_url):
        self.ws = WebSocket(ws_url)
        self.next_id = 0
        self.events = []

    def call(self, method, **params):
        self.next_id += 1
        my = self.next_id
        self.ws.send(json.dumps({"id": my, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == my:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            if "method" in msg:
                self.events.append(msg)

    def evaluate(self, expression):
        r = self.call("Runtime.evaluate", expression=expression, awaitPromise=True, returnByValue=True)
        if "exceptionDetails" in r:
            d = r["exceptionDetails"]
            text = d.get("exception", {}).get("description") or d.get("text")
            raise RuntimeError(f"page: {text}")
        return r["result"].get("value")

    def console_errors(self):
        errs = []
        for e in self.events:
            m, p = e["method"], e.get("params", {})
            if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                errs.append("console." + p["type"] + ": " + " ".join(str(a.get("value", a.get("description")))
                                                                   for a in p.get("args", [])))
            elif m == "Runtime.exceptionThrown":
                errs.append("exception: " + json.dumps(p.get("exceptionDetails", {}))[:400])
            elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
                errs.append("log: " + p["entry"].get("text", ""))
        return errs


class Chromium:
    """Headless Chromium with WebGL 2 on SwiftShader, one fresh profile."""

    def __init__(self, workdir):
        self.profile = tempfile.mkdtemp(prefix="chromium-", dir=workdir)
        exe = shutil.which("chromium") or "/usr/bin/chromium"
        args = [exe, "--headless", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--no-first-run", "--no-default-browser-check", "--mute-audio",
                f"--user-data-dir={self.profile}", "--remote-debugging-port=0",
                "--window-size=1000,800", "about:blank"]
        if os.geteuid() == 0:
            args.insert(1, "--no-sandbox")
        self.proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=open(os.path.join(workdir, "chromium.log"), "w"))
        port_file = os.path.join(self.profile, "DevToolsActivePort")
        deadline = time.time() + 60
        while not os.path.exists(port_file) or not open(port_file).read().strip():
            if self.proc.poll() is not None or time.time() > deadline:
                raise RuntimeError("chromium did not start (see chromium.log)")
            time.sleep(0.1)
        self.port = int(open(port_file).read().split()[0])

    def page(self, url):
        req = urllib.request.Request(f"http://127.0.0.1:{self.port}/json/new?about:blank", method="PUT")
        target = json.loads(urllib.request.urlopen(req, timeout=30).read())
        dt = DevTools(target["webSocketDebuggerUrl"])
        dt.call("Runtime.enable")
        dt.call("Log.enable")
        dt.call("Page.enable")
        dt.call("Page.navigate", url=url)
        return dt

    def close(self):
        self.proc.terminate()
        try:
            self.proc.wait(20)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        shutil.rmtree(self.profile, ignore_errors=True)


def wait_ready(dt):
    """The page's load result: ("ok", info) or ("error", message)."""
    deadline = time.time() + 120
    while time.time() < deadline:
        try:
            state = dt.evaluate("window.hwReady ? window.hwReady.then(v => ['ok', v], e => ['error', e.message]) : null")
        except RuntimeError:
            state = None
        if state:
            return state
        time.sleep(0.2)
    raise RuntimeError("the page never set window.hwReady")


def serve(folder):
    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):
            pass
    handler = functools.partial(Quiet, directory=folder)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


def run(cmd, name, cwd):
    t = time.time()
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    last = (r.stdout.strip().splitlines() or r.stderr.strip().splitlines() or [""])[-1]
    check(f"{name} exits 0", r.returncode == 0, f"{time.time() - t:.1f} s; {last}")
    if r.returncode != 0:
        print(r.stderr)
        sys.exit(1)
    return r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("hybridwalk")
    ap.add_argument("source_dir")
    ap.add_argument("--scene", default="indoor")
    ap.add_argument("--path", help="camera path JSON (default: the scene's built-in path)")
    ap.add_argument("--frames", type=int, default=31, help="frames of the path walked (0 = all)")
    ap.add_argument("--size", default="256x192", help="frame size WxH ('' = the path's)")
    ap.add_argument("--keep", help="work here and keep the files")
    ap.add_argument("--screenshot", help="also save a screenshot of the playing page here")
    ap.add_argument("--timing", help="time the page's frames (3 rounds) and write JSON here")
    ap.add_argument("--no-tamper", action="store_true")
    a = ap.parse_args()
    hw = os.path.abspath(a.hybridwalk)
    work = os.path.abspath(a.keep) if a.keep else tempfile.mkdtemp(prefix="hw-web-")
    os.makedirs(work, exist_ok=True)
    common = ["--scene", a.scene] + (["--path", os.path.abspath(a.path)] if a.path else [])
    common += ["--frames", str(a.frames)] if a.frames else []
    if a.size:
        sw, sh = a.size.split("x")
        common += ["--width", sw, "--height", sh]
    run([hw, "bake", *common, "--out", "db", "--quiet"], "bake", work)
    run([hw, "walk", *common, "--keyframes", "db", "--mode", "hybrid", "--no-render-holes",
         "--no-reference", "--save-frames", "--strips", "0", "--out", "walk", "--quiet"], "walk --keyframes", work)
    # Without --path: the scene's built-in path at the database's size.
    run([hw, "publish", "--keyframes", "db", "--out", "site"] + (["--path", os.path.abspath(a.path)] if a.path else []),
        "publish", work)
    site = os.path.join(work, "site")
    for f in ("index.html", "player.js", "manifest.json"):
        check(f"site has {f}", os.path.exists(os.path.join(site, f)))

    server = serve(work)
    base = f"http://127.0.0.1:{server.server_address[1]}"
    chrome = Chromium(work)
    try:
        dt = chrome.page(f"{base}/site/index.html?play=0")
        state, info = wait_ready(dt)
        check("page loads", state == "ok", json.dumps(info))
        if state != "ok":
            return
        frames = info["frames"]
        w, h = info["width"], info["height"]
        worst, worst_at, diffs = math.inf, -1, []
        for f in range(frames):
            px = base64.b64decode(dt.evaluate(f"window.hwRender({f})"))
            web = rgba_to_rgb(px)
            nw, nh, native = read_png(os.path.join(work, "walk", "frames", f"{f:04d}.png"))
            if (nw, nh) != (w, h):
                check(f"frame {f}: native size", False, f"{nw}x{nh} vs {w}x{h}")
                continue
            p = psnr(web, native)
            diffs.append(p)
            if p < worst:
                worst, worst_at = p, f
            if p < MIN_PSNR_DB or a.keep:
                write_png(os.path.join(work, f"web_{f:04d}.png"), w, h, web)
        finite = [p for p in diffs if math.isfinite(p)]
        print(f"{len(diffs)} frames, PSNR web vs native: min {worst:.2f} dB (frame {worst_at}), "
              f"median {sorted(finite)[len(finite) // 2] if finite else math.inf:.2f} dB, "
              f"{len(diffs) - len(finite)} identical")
        check(f"every frame >= {MIN_PSNR_DB} dB against the native walk", worst >= MIN_PSNR_DB,
              f"worst {worst:.2f} dB at frame {worst_at}")
        # A jump (the slider) replays the frames from the bracketing keyframe:
        # the same frame as drawn in order.
        jump = frames // 2 + 1
        dt.evaluate("window.hwRender(0), 1")
        _, _, native = read_png(os.path.join(work, "walk", "frames", f"{jump:04d}.png"))
        p = psnr(rgba_to_rgb(base64.b64decode(dt.evaluate(f"window.hwRender({jump})"))), native)
        check(f"frame {jump} after a jump from frame 0: >= {MIN_PSNR_DB} dB", p >= MIN_PSNR_DB, f"{p:.2f} dB")
        # Flying off the path with the keys and back (space), as a viewer does.
        def key(k, code, kind):
            dt.call("Input.dispatchKeyEvent", type=kind, key=k, code=code,
                    **({"text": k} if kind == "keyDown" and len(k) == 1 else {}))
        key("w", "KeyW", "keyDown")
        dt.evaluate("new Promise(r => setTimeout(r, 300))")
        key("w", "KeyW", "keyUp")
        dt.evaluate("new Promise(r => setTimeout(r, 100))")
        hud = dt.evaluate("document.getElementById('hud').textContent")
        check("W flies off the path", "off the path" in hud and "keyframes" in hud, hud.replace("\n", " | "))
        key(" ", "Space", "keyDown")
        key(" ", "Space", "keyUp")
        dt.evaluate("new Promise(r => setTimeout(r, 200))")
        hud = dt.evaluate("document.getElementById('hud').textContent")
        check("space returns to the path", hud.startswith("frame "), hud.replace("\n", " | "))
        if a.timing:
            t = dt.evaluate("window.hwTime(3)")
            t.update({"width": w, "height": h, "frames": frames, "scene": a.scene})
            json.dump(t, open(a.timing, "w"), indent=1)
            print("page timing:", json.dumps(t))
        if a.screenshot:  # the page as a viewer opens it, playing from a frame between keyframes
            sp = chrome.page(f"{base}/site/index.html?frame={frames * 3 // 8}")
            wait_ready(sp)
            sp.call("Emulation.setDeviceMetricsOverride", width=820, height=640, deviceScaleFactor=1, mobile=False)
            sp.evaluate("new Promise(r => setTimeout(r, 400))")
            shot = sp.call("Page.captureScreenshot", format="png")
            open(a.screenshot, "wb").write(base64.b64decode(shot["data"]))
            errs = sp.console_errors()
            check("no console errors while playing", not errs, "; ".join(errs)[:800])
        errs = dt.console_errors()
        check("no console errors", not errs, "; ".join(errs)[:800])

        if a.no_tamper:
            return
        # Damaged files: a clear message naming the file; nothing drawn.
        manifest = json.load(open(os.path.join(site, "manifest.json")))
        kf = manifest["keyframes"][1]
        cases = [
            ("truncated mesh", kf["mesh"]["file"], lambda b: b[:len(b) - 96],
             [kf["mesh"]["file"], "manifest.json says", "truncated"]),
            ("tampered mesh", kf["mesh"]["file"], lambda b: b[:100] + bytes([b[100] ^ 1]) + b[101:],
             [kf["mesh"]["file"], "checksum", "manifest.json says"]),
            ("tampered colour", kf["colour"]["file"], lambda b: b[:60] + bytes([b[60] ^ 4]) + b[61:],
             [kf["colour"]["file"], "checksum"]),
            ("truncated manifest", "manifest.json", lambda b: b[:len(b) // 2],
             ["manifest.json", "index.html says", "truncated"]),
            ("edited manifest", "manifest.json",
             lambda b: b.replace(b'"quads": %d' % kf["mesh"]["quads"], b'"quads": %d' % (kf["mesh"]["quads"] + 1), 1),
             ["manifest.json", "checksum", "index.html says"]),
            ("manifest edited, index.html updated", "manifest.json",
             lambda b: b.replace(b'"quads": %d' % kf["mesh"]["quads"], b'"quads": %d' % (kf["mesh"]["quads"] + 1), 1),
             [kf["mesh"]["file"], "quads", "manifest.json says"]),
            ("manifest not JSON, index.html updated", "manifest.json", lambda b: b[:len(b) // 2],
             ["manifest.json", "not valid JSON"]),
        ]
        for name, file, damage, words in cases:
            bad = os.path.join(work, "bad-" + name.replace(" ", "-"))
            shutil.rmtree(bad, ignore_errors=True)
            shutil.copytree(site, bad)
            raw = open(os.path.join(bad, file), "rb").read()
            open(os.path.join(bad, file), "wb").write(damage(raw))
            if "index.html updated" in name:  # consistently: the page's own check passes
                text = open(os.path.join(bad, "manifest.json"), "rb").read()
                html = open(os.path.join(bad, "index.html")).read()
                html = re.sub(r'name="hybridwalk-manifest" content="[^"]*"',
                              f'name="hybridwalk-manifest" content="{len(text)} {hw32(text):08x}"', html)
                open(os.path.join(bad, "index.html"), "w").write(html)
            d = chrome.page(f"{base}/{os.path.basename(bad)}/index.html")
            state, msg = wait_ready(d)
            shown = d.evaluate("document.getElementById('error').hidden ? '' : document.getElementById('error').textContent")
            drawn = d.evaluate("!document.getElementById('wrap').hidden")
            check(f"{name}: refused with a message naming {file}", state == "error" and all(x in shown for x in words),
                  shown)
            check(f"{name}: nothing drawn", not drawn)
    finally:
        chrome.close()
        server.shutdown()
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
    if failures:
        print(f"{len(failures)} check(s) failed: {', '.join(failures)}")
        sys.exit(1)
    print("all checks passed")
