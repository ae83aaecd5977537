"""Benchmark: the explorer's update latency, in the server and seen from a real browser.

Work: the page of ``stickslip explore`` (law F1, ``c = 3.8``) with the
driving-velocity slider set to ``--n`` positions over two decades. Each update
computes the steady cycle (``stickslip.cycle``, with the probe for a second
attractor), the motion from rest through three cycles (1500 samples), the
amplitude-velocity curve (25 cycles) and the criterion.

* the server: :func:`stickslip.explore.compute` per set-up, timed in this process;
* the browser: the slider's value set in headless Chromium (BokehJS), timed until
  the spring-force plot holds the new data, over the page's websocket;
* SciPy: the steady cycle of the same set-ups the straightforward way
  (``solve_ivp`` DOP853 with events, as in ``bench_cycles.py``), which is only the
  first of the update's four computations.

Run: ``python benchmarks/bench_explore.py [--n 40]`` (the browser part needs
Debian's ``chromium`` and ``chromium-driver``; it is skipped without them).
"""

from __future__ import annotations

import argparse
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_cycles import scipy_cycle

from stickslip.explore import Setup, compute


def _browser_latencies(log_nus: np.ndarray) -> list[tuple[float, float]]:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    proc = subprocess.Popen(
        [sys.executable, "-m", "stickslip.cli", "explore", "--port", str(port), "--no-browser"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    url = f"http://127.0.0.1:{port}/"
    opts = webdriver.ChromeOptions()
    opts.binary_location = shutil.which("chromium") or ""
    flags = ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"]
    flags += ["--disable-background-networking", "--disable-component-update", "--disable-sync"]
    for flag in flags:
        opts.add_argument(flag)
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=opts)
    try:
        for _ in range(600):
            try:
                urllib.request.urlopen(url, timeout=5).read()
                break
            except OSError:
                time.sleep(0.2)
        driver.get(url)
        driver.set_script_timeout(60)
        get_y = "return Array.from(Bokeh.documents[0].get_model_by_name('force').data.y).slice(-5);"
        for _ in range(1200):
            try:
                if driver.execute_script(get_y):
                    break
            except Exception:
                pass
            time.sleep(0.1)
        # in the page: set the slider's value, resolve when the spring-force data has changed
        # and the page has been painted twice since (the new plots are on screen), timed by
        # the browser's clock, without the webdriver's own round trips
        timed = """
            const done = arguments[arguments.length - 1];
            const doc = Bokeh.documents[0];
            const src = doc.get_model_by_name('force');
            const t0 = performance.now();
            src.connect(src.change, () => {
                const t_data = performance.now() - t0;
                const painted = () => done([t_data, performance.now() - t0]);
                requestAnimationFrame(() => requestAnimationFrame(painted));
            });
            doc.get_model_by_name('nu').value = arguments[0];
        """
        out = []
        for x in log_nus:
            t_data, t_paint = driver.execute_async_script(timed, float(x))
            out.append((t_data / 1e3, t_paint / 1e3))
            time.sleep(0.05)
        return out
    finally:
        driver.quit()
        proc.terminate()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=40)
    a = parser.parse_args()
    log_nus = np.round(np.linspace(-2.5, -0.5, a.n), 2)
    nus = 10.0**log_nus
    compute(Setup(nu=0.01))  # compile and warm up
    server = []
    for nu in nus:
        t0 = time.perf_counter()
        compute(Setup(nu=float(nu)))
        server.append(time.perf_counter() - t0)
    t0 = time.perf_counter()
    for nu in nus:
        scipy_cycle(float(nu), 3.8, rtol=1e-10, atol=1e-12)
    scipy_per = (time.perf_counter() - t0) / len(nus)
    s = np.array(server)
    print(f"explorer update, {a.n} slider positions (nu from 10^-2.5 to 10^-0.5, F1 c = 3.8)")
    med = np.median(s)
    print(
        f"  server (cycle + motion + curve + criterion):  median {1e3 * med:.1f} ms, "
        f"max {1e3 * s.max():.1f} ms"
    )
    print(
        f"  SciPy solve_ivp, the steady cycle alone:              median {1e3 * scipy_per:.1f} ms per set-up"
    )
    print(f"  ratio: the whole update is {scipy_per / med:.1f}x faster than SciPy's cycle alone")
    if shutil.which("chromium") and shutil.which("chromedriver"):
        b = np.array(_browser_latencies(log_nus))
        for j, what in enumerate(("new plot data in the page", "new plots painted")):
            x = 1e3 * b[:, j]
            print(f"  browser, slider value -> {what:26s} median {np.median(x):.1f} ms, "
                  f"95th percentile {np.percentile(x, 95):.1f} ms, max {x.max():.1f} ms")  # fmt: skip
    else:
        print("  browser: skipped (no chromium/chromedriver)")


if __name__ == "__main__":
    main()
