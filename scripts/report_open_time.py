"""How fast `voussoir report`'s page opens: the Armadillo with its mechanism (issue #72's goal:
≤ 5 MB, open in ≤ 2 s in the test browser), each run in a fresh headless Chromium as the browser
tests start it (tests/python/test_report_browser.py's `Page`), given two seconds to finish
starting (as a user's browser has: a page opened while Chromium still starts its helper
processes takes ~0.7 s longer on 2 cores). Prints the size and the medians of
the design drawn (`voussoir.shownAt`) and the mechanism playing (`voussoir.readyAt`), ms since
navigation. By hand, in the Python tests' environment:

    ${TMPDIR:-/tmp}/voussoir-python-tests/bin/python scripts/report_open_time.py [--runs 5]

(VOUSSOIR_BIN names the binary; default: the debug build in target/.)
"""

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "python"))
from test_report_browser import Page, report  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        out = report(Path(tmp) / "armadillo.html", "assets/compas/compas_cra/armadillo_cra.json",
                     "--mu", "0.84", "--accel", "1,0,0", "--robustness")
        shown, ready = [], []
        for _ in range(args.runs):
            page = Page()
            try:
                time.sleep(2.0)
                page.open(out)
                shown.append(page.js("window.voussoir.shownAt"))
                ready.append(page.js("window.voussoir.readyAt"))
            finally:
                page.close()
        print(f"{out.stat().st_size / 1e6:.2f} MB; design drawn: median {statistics.median(shown):.0f} ms "
              f"(min {min(shown):.0f}, max {max(shown):.0f}); mechanism playing: median "
              f"{statistics.median(ready):.0f} ms (min {min(ready):.0f}, max {max(ready):.0f}), {args.runs} fresh browsers")


if __name__ == "__main__":
    main()
