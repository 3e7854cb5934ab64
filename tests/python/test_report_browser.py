"""`voussoir report` opened in a real browser: Debian's Chromium, headless, driven over the
DevTools protocol on a pipe (`--remote-debugging-pipe`), with the network switched off.

Each test writes a report with the voussoir binary (VOUSSOIR_BIN), opens it from a file, waits
until the page says it is ready, and reads the page as a user sees it: screenshots (Pillow), real
mouse clicks, the text on the page. Invariants are stated in each test. Every page must log no
error and fetch nothing but its own file, `data:` and `blob:` URLs.

scripts/test installs Chromium when it is missing; without it these tests fail (they are the
report's only test in a browser).
"""

import io
import json
import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

ROOT = Path(__file__).resolve().parents[2]
BIN = os.environ.get("VOUSSOIR_BIN", str(ROOT / "target" / "debug" / "voussoir"))
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
WIDTH, HEIGHT = 1400, 900


class Page:
    """One Chromium with one page, over the DevTools protocol's pipe (fd 3 in, fd 4 out)."""

    def __init__(self):
        assert CHROMIUM, "no chromium on PATH: scripts/test installs Debian's chromium package"
        self.profile = tempfile.mkdtemp(prefix="voussoir-chromium-")
        to_browser = os.pipe()
        from_browser = os.pipe()

        def pipes_at_3_and_4():
            a, b = os.dup(to_browser[0]), os.dup(from_browser[1])
            os.dup2(a, 3)
            os.dup2(b, 4)

        self.proc = subprocess.Popen(
            [CHROMIUM, "--headless", "--no-sandbox", "--remote-debugging-pipe", "--no-first-run",
             "--enable-unsafe-swiftshader", "--use-angle=swiftshader", "--hide-scrollbars",
             f"--user-data-dir={self.profile}", f"--window-size={WIDTH},{HEIGHT}", "about:blank"],
            preexec_fn=pipes_at_3_and_4, pass_fds=(3, 4),
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_browser[0])
        os.close(from_browser[1])
        self.out = os.fdopen(to_browser[1], "wb", buffering=0)
        self.inp = os.fdopen(from_browser[0], "rb", buffering=0)
        self.buffer = b""
        self.next_id = 0
        self.session = None
        self.errors, self.requests = [], []
        target = self.send("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.send("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        for domain in ["Page", "Runtime", "Log", "Network"]:
            self.send(f"{domain}.enable")
        self.send("Network.emulateNetworkConditions", offline=True, latency=0,
                  downloadThroughput=-1, uploadThroughput=-1)
        self.send("Emulation.setDeviceMetricsOverride", width=WIDTH, height=HEIGHT,
                  deviceScaleFactor=1, mobile=False)

    def _message(self):
        while b"\0" not in self.buffer:
            chunk = self.inp.read(1 << 16)
            assert chunk, "chromium closed its pipe"
            self.buffer += chunk
        text, self.buffer = self.buffer.split(b"\0", 1)
        return json.loads(text)

    def _event(self, m):
        method, p = m.get("method"), m.get("params", {})
        if method == "Runtime.exceptionThrown":
            self.errors.append(p["exceptionDetails"].get("exception", {}).get("description", str(p)))
        elif method == "Runtime.consoleAPICalled" and p["type"] == "error":
            self.errors.append(" ".join(str(a.get("value", a.get("description"))) for a in p["args"]))
        elif method == "Log.entryAdded" and p["entry"]["level"] == "error":
            self.errors.append(p["entry"]["text"])
        elif method == "Network.requestWillBeSent":
            self.requests.append(p["request"]["url"])

    def send(self, method, **params):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params}
        if self.session:
            message["sessionId"] = self.session
        self.out.write(json.dumps(message).encode() + b"\0")
        while True:
            m = self._message()
            if m.get("id") == self.next_id:
                assert "error" not in m, f"{method}: {m['error']}"
                return m.get("result", {})
            self._event(m)

    def js(self, expression):
        r = self.send("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        assert "exceptionDetails" not in r, f"{expression}: {r['exceptionDetails']}"
        return r["result"].get("value")

    def open(self, path, timeout=30.0, ready="window"):
        self.send("Page.navigate", url=Path(path).resolve().as_uri())
        end = time.time() + timeout
        # (A frame's window may not exist yet while the page loads.)
        while not self.js(f"(() => {{ try {{ return !!{ready}.voussoir.ready; }} catch (e) {{ return false; }} }})()"):
            assert time.time() < end, f"{path}: not ready after {timeout} s; errors: {self.errors}"
            time.sleep(0.05)
        self.settle()

    def settle(self):
        """Lets the page draw what it was just asked to (two animation frames)."""
        self.js("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")

    def wait_until(self, expression, timeout=30.0):
        """Polls a condition the page reaches asynchronously (a mode loads its glTF first)."""
        end = time.time() + timeout
        while not self.js(expression):
            assert time.time() < end, f"{expression}: not true after {timeout} s; errors: {self.errors}"
            time.sleep(0.05)
        self.settle()

    def rect(self, selector):
        return self.js(f"(() => {{ const r = document.querySelector({json.dumps(selector)}).getBoundingClientRect();"
                       " return [r.left, r.top, r.width, r.height]; })()")

    def click(self, x, y):
        for kind in ["mousePressed", "mouseReleased"]:
            self.send("Input.dispatchMouseEvent", type=kind, x=x, y=y, button="left", clickCount=1)
        self.settle()

    def click_on(self, selector, fx=0.5, fy=0.5):
        left, top, w, h = self.rect(selector)
        self.click(left + fx * w, top + fy * h)

    def shot(self, selector):
        """The element's pixels as an (h, w, 3) array, and its page rectangle."""
        left, top, w, h = self.rect(selector)
        data = self.send("Page.captureScreenshot", format="png",
                         clip={"x": left, "y": top, "width": w, "height": h, "scale": 1})["data"]
        import base64
        img = Image.open(io.BytesIO(base64.b64decode(data))).convert("RGB")
        return np.asarray(img).astype(int), (left, top)

    def close(self):
        self.proc.kill()
        self.proc.wait()
        # Chromium's helper processes may still write into the profile for a moment.
        for _ in range(20):
            shutil.rmtree(self.profile, ignore_errors=True)
            if not os.path.exists(self.profile):
                break
            time.sleep(0.05)

    def assert_clean(self):
        """No error logged; nothing fetched but the file itself, data: and blob: URLs."""
        assert self.errors == [], self.errors
        foreign = [u for u in self.requests if not u.startswith(("file:", "data:", "blob:"))]
        assert foreign == [], foreign


@pytest.fixture
def page():
    p = Page()
    yield p
    p.close()


@pytest.fixture
def tmp(tmp_path):
    return tmp_path


def report(out, *args):
    r = subprocess.run([BIN, "report", *args, "-o", str(out)], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode in (0, 1), r.stderr
    return out


def analysis_json(tmp, scene, *args):
    out = tmp / "report.json"
    r = subprocess.run([BIN, "analyze", scene, *args, "--json", str(out)], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode in (0, 1), r.stderr
    return json.loads(out.read_text())


def srgb8(linear):
    c = np.clip(np.asarray(linear, float), 0, 1)
    s = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    return np.round(255 * s)


def hex_rgb(css):
    return np.array([int(css[k:k + 2], 16) for k in (1, 3, 5)])


def count_colour(pixels, rgb, tol=3):
    return int((np.abs(pixels - np.asarray(rgb)).max(axis=2) <= tol).sum())


# The diagram colours (src/viz/colors.rs, linear RGB).
BLUE_LIGHT, BLUE_DEEP = [0.72, 0.82, 1.0], [0.02, 0.15, 0.75]
YELLOW, GREY, RED = [1.0, 0.9, 0.1], [0.55, 0.55, 0.55], [0.85, 0.05, 0.05]
ORANGE_LIGHT, ORANGE_DEEP = [1.0, 0.45, 0.05], [0.85, 0.17, 0.0]


def friction_colour(u, t):
    """The friction diagram's colour of use u against threshold t (src/viz/colors.rs)."""
    if u <= 0:
        return GREY
    if u <= t:
        return YELLOW
    s = min(1.0, (u - t) / (1 - t))
    return list(np.add(np.multiply(1 - s, ORANGE_LIGHT), np.multiply(s, ORANGE_DEEP)))


def test_fig6_friction_mode_shows_each_joint_in_its_bands_colour(page, tmp):
    """Invariant: with the blocks hidden, every loaded joint of fig6 shows in the colour the
    friction diagram gives its use in the JSON report (yellow up to the threshold, orange shaded
    by the use above it), exactly as the legend's colours are computed (unlit, sRGB, within
    3/255), and the page's legend lists the four bands. The threshold 0.2 puts fig6's joints in
    both bands (uses 0.07, and 0.24 and 0.40)."""
    t = 0.2
    out = report(tmp / "fig6f.html", "assets/cases/fig6_dmsc.json", "--mode", "friction", "--threshold", str(t))
    rep = analysis_json(tmp, "assets/cases/fig6_dmsc.json")
    uses = [r["friction_utilization"] for r in rep["interfaces"] if r["compression"] > 0 and r["friction_utilization"] > 0]
    page.open(out)
    legend = page.js("[...document.querySelectorAll('#legend .swatch')].map(s => getComputedStyle(s).backgroundColor)")
    assert len(legend) == 4 and "rgb(255, 243, 89)" in legend, legend
    page.click_on("#blocks-toggle")
    assert page.js("document.getElementById('blocks-toggle').textContent") == "show"
    px, _ = page.shot("#design-view")
    assert any(u <= t for u in uses) and any(u > t for u in uses), uses
    for u in uses:
        colour = srgb8(friction_colour(u, t))
        assert count_colour(px, colour) > 50, (u, colour)
    assert count_colour(px, srgb8(RED)) == 0, "fig6 stands: nothing beyond μ"
    page.assert_clean()


def test_fig6_compression_mode_is_blue_on_the_legends_scale(page, tmp):
    """Invariant: every strongly coloured interface pixel of the compression diagram lies on the
    legend's scale from light to deep blue (the colour of a vertex's share of its face's
    largest force, interpolated in linear RGB and shown in sRGB), within 8/255; no tension red."""
    out = report(tmp / "fig6c.html", "assets/cases/fig6_dmsc.json", "--mode", "compression")
    page.open(out)
    page.click_on("#blocks-toggle")
    px = page.shot("#design-view")[0]
    blue = px[(px[..., 2] - px[..., 0] > 60) & (px[..., 2] > px[..., 1] + 30)]
    assert len(blue) > 500, len(blue)
    scale = np.array([srgb8(np.add(np.multiply(1 - s, BLUE_LIGHT), np.multiply(s, BLUE_DEEP)))
                      for s in np.linspace(0, 1, 201)])
    distance = np.abs(blue[:, None, :] - scale[None, :, :]).max(axis=2).min(axis=1)
    # Edges are antialiased against the white background: the bulk lies on the scale.
    assert np.mean(distance <= 8) > 0.95, np.percentile(distance, [50, 90, 99])
    assert count_colour(px, srgb8(RED)) == 0
    page.assert_clean()


def test_the_vectors_diagram_draws_each_resultant_as_an_arrow(page, tmp):
    """Invariant: switching to vectors (a real click on its button) keeps the compression
    colours and adds the resultants' arrows: dark pixels (the arrows' colour, #222) appear that
    the compression diagram does not have, around the resultant points the JSON report gives."""
    out = report(tmp / "fig6.html", "assets/cases/fig6_dmsc.json")
    page.open(out)
    page.click_on("#blocks-toggle")
    before = page.shot("#design-view")[0]
    page.click_on("#modes button[data-mode=vectors]")
    page.wait_until("document.getElementById('legend').textContent.includes('arrows')")
    after, (left, top) = page.shot("#design-view")
    dark = lambda px: (px.max(axis=2) < 70)
    new_dark = dark(after) & ~dark(before)
    assert new_dark.sum() > 100, new_dark.sum()
    ys, xs = np.nonzero(new_dark)
    points = [page.js(f"window.voussoir.onPage('interface', {r['index']})")
              for r in page.js("window.voussoir.report().then(r => r.interfaces)") if r["resultant_point"]]
    near = min(min(abs(x + left - p["x"]) + abs(y + top - p["y"]) for p in points) for x, y in zip(xs[::50], ys[::50]))
    assert near < 60, near
    page.assert_clean()


def test_a_click_on_an_interface_shows_its_normal_force_as_the_json_report_gives_it(page, tmp):
    """Invariant: a real click at an interface's resultant point selects an interface, and the
    panel shows that interface's normal force equal to `voussoir analyze --json`'s (6 digits)."""
    out = report(tmp / "fig6.html", "assets/cases/fig6_dmsc.json")
    rep = analysis_json(tmp, "assets/cases/fig6_dmsc.json")
    page.open(out)
    largest = max(rep["interfaces"], key=lambda r: r["normal_force"])
    at = page.js(f"window.voussoir.onPage('interface', {largest['index']})")
    page.click(at["x"], at["y"])
    page.wait_until("!document.getElementById('info').textContent.startsWith('Click')")
    info = page.js("document.getElementById('info').textContent")
    assert info.startswith("interface "), info
    shown = int(info.split()[1].rstrip(":"))
    expected = rep["interfaces"][shown]
    line = next(l for l in info.splitlines() if l.startswith("normal force"))
    value = float(line.split()[2])
    assert value == pytest.approx(expected["normal_force"], rel=1e-5), (line, expected["normal_force"])
    assert f"{expected['a']} | {expected['b']}" in info
    assert shown == largest["index"], "the click at its resultant point picks that interface"
    page.assert_clean()


def assert_motion_advances(page, moved_min):
    """Two scrubbed times differ where the moved blocks are, and only there."""
    page.click_on("#scrub", 0.0, 0.5)
    a, (left, top) = page.shot("#motion-view")
    rects_a = page.js("window.voussoir.movingRects()")
    page.click_on("#scrub", 0.9, 0.5)
    assert page.js("window.voussoir.player.time") > 0
    b, _ = page.shot("#motion-view")
    rects_b = page.js("window.voussoir.movingRects()")
    assert len(rects_a) >= moved_min
    changed = np.abs(a - b).max(axis=2) > 40
    assert changed.sum() > 100, changed.sum()
    inside = np.zeros_like(changed)
    h, w = changed.shape
    for r in rects_a + rects_b:
        x0, y0, x1, y1 = r["rect"]
        inside[max(0, int(y0 - top) - 4):min(h, int(y1 - top) + 5), max(0, int(x0 - left) - 4):min(w, int(x1 - left) + 5)] = True
    outside = changed & ~inside
    assert outside.sum() == 0, f"{outside.sum()} changed pixels outside the moved blocks"
    return a


def test_the_arch_report_plays_its_mechanism_with_the_moved_blocks_in_violet(page, tmp):
    """Invariant: the default arch's report with --robustness shows λ* in the caption as the
    robustness command prints it, draws the mechanism's moving blocks in the moved colour, and
    its animation changes the picture where those blocks are and only there."""
    out = report(tmp / "arch.html", "--robustness")
    r = subprocess.run([BIN, "robustness"], capture_output=True, text=True, cwd=ROOT)
    lam = next(l for l in r.stdout.splitlines() if l.startswith("LOAD FACTOR")).split("=")[1].split(":")[0].strip()
    page.open(out)
    assert f"λ* = {lam}" in page.js("document.getElementById('caption').textContent")
    a = assert_motion_advances(page, moved_min=1)
    r_, g, b = a[..., 0], a[..., 1], a[..., 2]
    violet = ((b > r_ + 20) & (r_ > g + 15)).sum()
    assert violet > 500, violet
    page.assert_clean()


def test_a_drop_test_report_animates_the_fall(page, tmp):
    """Invariant: a thin arch that does not stand falls in the drop test's pane: two scrubbed
    times differ, only where the moved blocks are."""
    out = report(tmp / "drop.html", "builtin:arch?n=9&t=0.04", "--dynamic", "--duration", "1")
    page.open(out)
    assert page.js("document.querySelector('#tabs button').textContent") == "drop test"
    assert_motion_advances(page, moved_min=3)
    page.assert_clean()


def box(name, x0, y0, z0, x1, y1, z1):
    v = [[x, y, z] for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    return {"name": name, "vertices": v, "faces": faces}


@pytest.mark.parametrize("blocks, interfaces", [
    ([box("a", 0, 0, 0, 1, 1, 1)], 0),
    ([box("a", 0, 0, 0, 1, 1, 1), box("b", 0, 0, 1, 1, 1, 2)], 1),
])
def test_designs_that_touch_no_support_say_so(page, tmp, blocks, interfaces):
    """Invariant: a block touching nothing (no interfaces) and a stack of two touching no
    support (one interface) give pages that say the design is not supported, and the first that
    it has no interfaces, with the verdict, and no error."""
    scene = tmp / "unsupported.json"
    scene.write_text(json.dumps({"name": "unsupported", "blocks": blocks}))
    out = report(tmp / "unsupported.html", str(scene))
    page.open(out)
    text = page.js("document.body.innerText")
    assert "not supported" in text and "DOES NOT STAND: something touches no support" in text
    assert ("no interfaces" in text.lower()) == (interfaces == 0)
    assert page.js("window.voussoir.data.detected") == interfaces
    assert f"{interfaces} interfaces" in text
    if interfaces:
        assert f"No forces: {interfaces} interface(s), but nothing holds the design" in text
    page.assert_clean()


def test_the_armadillo_with_its_mechanism_fits_in_5_mb_and_opens(page, tmp):
    """Invariant: the Armadillo's report with its mechanism is ≤ 5 MB, and it opens in a fresh
    browser with its design drawn and its mechanism playing, no error. How fast is measured by
    scripts/report_open_time.py (docs/benchmarks.md), not asserted here: the machine is shared."""
    out = report(tmp / "armadillo.html", "assets/compas/compas_cra/armadillo_cra.json",
                 "--mu", "0.84", "--accel", "1,0,0", "--robustness")
    assert out.stat().st_size <= 5 * 1024 * 1024, out.stat().st_size
    page.open(out)
    shown_ms, ready_ms = page.js("window.voussoir.shownAt"), page.js("window.voussoir.readyAt")
    print(f"armadillo report: {out.stat().st_size / 1e6:.2f} MB, open after {shown_ms:.0f} ms, "
          f"its mechanism playing after {ready_ms:.0f} ms")
    assert page.js("window.voussoir.data.motions[0].moved.length") == 366
    page.assert_clean()


def assets_of(page_html):
    return dict(re.findall(r'data-asset="([^"]+)">([^<]*)</script>', page_html))


def test_python_report_writes_the_command_lines_page(tmp):
    """Invariant: voussoir.report returns the page it writes, and that page embeds the same
    designs, mechanism and three.js as the command line's for the same scene (one writer)."""
    import voussoir
    cli = report(tmp / "cli.html", "builtin:arch?n=15&t=0.15", "--robustness").read_text()
    py = voussoir.report(voussoir.Scene.builtin("arch?n=15&t=0.15"), robustness=True, path=tmp / "py.html")
    assert (tmp / "py.html").read_text() == py
    a, b = assets_of(py), assets_of(cli)
    assert list(a) == list(b) and len(a) == 10
    # The JSON report holds the run's timings; everything else is the same bytes.
    assert {k: v for k, v in a.items() if k != "report.json"} == {k: v for k, v in b.items() if k != "report.json"}
    with pytest.raises(voussoir.InputError, match="mode"):
        voussoir.report(voussoir.Scene.builtin("arch?n=15&t=0.15"), mode="sideways")
    scene_file = ROOT / "assets/cases/fig6_dmsc.json"
    before = scene_file.read_bytes()
    with pytest.raises(voussoir.InputError, match="overwrite"):
        voussoir.report(voussoir.Scene.from_file(str(scene_file)), path=scene_file)
    assert scene_file.read_bytes() == before


def test_an_analysis_shows_its_report_in_a_notebook(page, tmp):
    """Invariant: Analysis._repr_html_ (Jupyter's display) is an iframe whose page runs where a
    notebook puts it: inside another page, it gets ready with the analysis's verdict and the
    JSON report's interfaces, and logs no error."""
    import voussoir
    a = voussoir.analyze(voussoir.Scene.builtin("arch?n=15&t=0.15"))
    html = a._repr_html_()
    assert html.startswith("<iframe srcdoc=")
    notebook = tmp / "notebook.html"
    notebook.write_text("<!DOCTYPE html><html><body><h1>a notebook cell</h1>" + html + "</body></html>")
    frame = "document.querySelector('iframe').contentWindow"
    page.open(notebook, ready=frame)
    assert page.js(f"{frame}.document.getElementById('verdict').textContent") == "STANDS: compression and friction suffice"
    assert page.js(f"{frame}.voussoir.report().then(r => r.interfaces.length)") == len(a.normal_force)
    page.assert_clean()
