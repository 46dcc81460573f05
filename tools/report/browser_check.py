#!/usr/bin/env python3
"""Opens a report's report.html in headless Chromium and checks what a reader would see.

For each window width: every image loaded (complete, non-zero natural width), and no element
reaching past the right edge of the window unless it sits inside a scrolling box that itself fits
(wide tables scroll inside their box; the page must not). Writes a screenshot of the top of the page
at the first width. Prints one JSON object; exit 0 when every check passes, 1 when one fails, 2 when
Chromium is missing or does not answer.

  python3 tools/report/browser_check.py results/paper-quick/report --screenshot out/report.png
"""
import argparse
import json
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

# Runs after every image has loaded; appends the findings to the page as <pre id="browser-check">.
PROBE = """<script>
window.addEventListener('load', function () {
  var W = window.innerWidth;
  var out = {width: W, page_width: document.documentElement.scrollWidth, images: 0, broken: [], too_wide: []};
  document.querySelectorAll('img').forEach(function (im) {
    out.images++;
    if (!im.complete || im.naturalWidth === 0) out.broken.push(im.getAttribute('src'));
  });
  function inScroller(e) {
    for (var a = e.parentElement; a; a = a.parentElement) {
      var o = getComputedStyle(a).overflowX;
      if (o === 'auto' || o === 'scroll') return a.getBoundingClientRect().right <= W + 1;
    }
    return false;
  }
  document.querySelectorAll('body *').forEach(function (e) {
    var r = e.getBoundingClientRect();
    if (r.width > 0 && r.right > W + 1 && !inScroller(e))
      out.too_wide.push(e.tagName.toLowerCase() + (e.id ? '#' + e.id : '') + ' reaches ' + Math.round(r.right) + ' px');
  });
  var pre = document.createElement('pre');
  pre.id = 'browser-check';
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});
</script>"""


def chromium():
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def browse(exe, args, timeout=120):
    # --no-sandbox: CI runs as root, where Chromium refuses its sandbox.
    cmd = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("report_dir")
    ap.add_argument("--width", type=int, action="append", help="window width in px (repeatable; default 1280 and 800)")
    ap.add_argument("--screenshot", help="PNG of the top of the page at the first width")
    args = ap.parse_args()
    widths = args.width or [1280, 800]
    report = pathlib.Path(args.report_dir) / "report.html"
    if not report.is_file():
        print(f"browser_check: no {report}", file=sys.stderr)
        return 2
    exe = chromium()
    if not exe:
        print("browser_check: Chromium not found (scripts/install-deps installs the Debian package 'chromium')",
              file=sys.stderr)
        return 2
    html = report.read_text(encoding="utf-8")
    if "</body>" not in html:
        print(f"browser_check: {report} has no </body>", file=sys.stderr)
        return 1
    result = {"report": str(report), "chromium": exe, "widths": []}
    ok = True
    # The probe page sits beside report.html so that its relative image paths resolve.
    with tempfile.NamedTemporaryFile("w", suffix=".html", prefix=".browser_check_", dir=report.parent,
                                     encoding="utf-8", delete=False) as f:
        f.write(html.replace("</body>", PROBE + "</body>", 1))
        probe = pathlib.Path(f.name)
    try:
        for w in widths:
            r = browse(exe, [f"--window-size={w},900", "--virtual-time-budget=10000", "--dump-dom", probe.as_uri()])
            m = re.search(r'<pre id="browser-check">(.*?)</pre>', r.stdout, re.S)
            if not m:
                print(f"browser_check: Chromium gave no answer at width {w} (exit {r.returncode}): {r.stderr[-500:]}",
                      file=sys.stderr)
                return 2
            found = json.loads(m.group(1).replace("&quot;", '"').replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">"))
            found["ok"] = not found["broken"] and not found["too_wide"] and found["images"] > 0
            ok &= found["ok"]
            result["widths"].append(found)
        if args.screenshot:
            shot = pathlib.Path(args.screenshot).resolve()
            shot.parent.mkdir(parents=True, exist_ok=True)
            browse(exe, [f"--window-size={widths[0]},900", f"--screenshot={shot}", report.resolve().as_uri()])
            result["screenshot"] = str(shot)
            if not shot.is_file() or shot.stat().st_size == 0:
                print(f"browser_check: no screenshot written to {shot}", file=sys.stderr)
                ok = False
    finally:
        probe.unlink()
    result["ok"] = ok
    print(json.dumps(result, indent=1))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
