#!/usr/bin/python3
"""The browser viewer end to end: `sear view` serves the page, Debian's chromium (headless, through
Selenium) loads it, and we check what a user would see: no console errors, a scene that is drawn and
moves, keys that drive a robot in the simulation, pause that holds sim time, and a replay that opens.

Usage: viewer_test.py SEAR_BINARY [IR_PROBE]; the hills and live-plot case runs only with the probe.
Exit 77 (skipped) when chromium, chromedriver or Selenium are missing, unless CI is set: there a
missing tool fails, named."""

import csv
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

SKIP = 77
CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
CHROME_ARGS = ["--headless=new", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
               "--disable-background-networking", "--disable-component-update", "--disable-sync",
               "--no-first-run", "--window-size=1200,800"]

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)
    return ok


def missing_tools():
    missing = [p for p in (CHROMIUM, CHROMEDRIVER) if not os.access(p, os.X_OK)]
    for module, package in (("selenium", "python3-selenium"), ("PIL", "python3-pil")):
        try:
            __import__(module)
        except ImportError:
            missing.append(package)
    return missing


# ---- projects written for the test

# The robot the screenshots follow drives itself by script (no firmware to build); the second one
# has no MCU and no script, so only the keys move it. It stands 2 m to the side, out of mover's way.
PROJECT = """<project name="viewer_test">
  <run duration="{duration}" seed="1" trace_rate="50"/>
  <world step="0.001">
    <wall name="east" from="4 -1.5" to="4 1.5" height="0.4" thickness="0.15"/>
  </world>
  <robot file="{robots}/rover.xml" name="mover">
    <pose x="0" y="0"/>
    <script>
      <motor t="0" name="left" duty="0.8" dir="forward"/>
      <motor t="0" name="right" duty="0.8" dir="forward"/>
    </script>
  </robot>
  <robot file="{robots}/rover.xml" name="driven">
    <pose x="0" y="2"/>
  </robot>
</project>
"""


def write_project(folder, duration, robots):
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "project.xml")
    with open(path, "w") as f:
        f.write(PROJECT.format(duration=duration, robots=robots))
    return path


# ---- sear view, in its own process group so that killing it leaves nothing behind

class Viewer:
    def __init__(self, args, env):
        self.lines = []
        self.proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                                     env=env, start_new_session=True)
        self.url = None
        got = threading.Event()

        def read():
            for line in self.proc.stderr:
                self.lines.append(line)
                m = re.search(r"viewer on (http://\S+)", line)
                if m and not self.url:
                    self.url = m.group(1)
                    got.set()
            got.set()
        threading.Thread(target=read, daemon=True).start()
        got.wait(20)
        if not self.url:
            self.stop()
            raise RuntimeError("no 'viewer on URL' from %s:\n%s" % (" ".join(args), "".join(self.lines)))

    def stop(self):
        if self.proc.poll() is None:
            try:
                os.killpg(self.proc.pid, signal.SIGTERM)
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                os.killpg(self.proc.pid, signal.SIGKILL)
                self.proc.wait()
            except ProcessLookupError:
                pass

    def wait(self, seconds):
        try:
            return self.proc.wait(seconds)
        except subprocess.TimeoutExpired:
            return None


def browser(profile):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for a in CHROME_ARGS:
        options.add_argument(a)
    options.add_argument("--user-data-dir=" + profile)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)


def dataset(driver, key):
    return driver.execute_script("return document.body.dataset[arguments[0]]", key)


def wait_for(what, predicate, timeout):
    end = time.time() + timeout
    while time.time() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.05)
    return predicate()


def canvas_shot(driver):
    """The 3D view only (not the panels), as a PIL image."""
    import io
    from PIL import Image
    rect = driver.execute_script("var r = document.getElementById('view').getBoundingClientRect();"
                                 "return [r.left, r.top, r.right, r.bottom, window.devicePixelRatio];")
    image = Image.open(io.BytesIO(driver.get_screenshot_as_png())).convert("RGB")
    s = rect[4]
    return image.crop((int(rect[0] * s), int(rect[1] * s), int(rect[2] * s), int(rect[3] * s)))


def path_pixels(image):
    """Pixels of the robots' path colour (0xff8c1a, unlit): strong red, middling green, little blue;
    above the bottom 40 px, where the legend shows that colour too."""
    w, h = image.size
    data = image.load()
    return sum(1 for y in range(h - 40) for x in range(w)
               if data[x, y][0] > 200 and 110 < data[x, y][1] < 170 and data[x, y][2] < 80)


def robot_pixels(image):
    """Pixels of the first robot's colour (0xff2a00, unlit in the page): strong red, little green or
    blue. Nothing else in the scene is near it (terrain greens and browns, grey walls, yellow cones,
    magenta hits: each fails one of the three bounds)."""
    xs, ys = [], []
    w, h = image.size
    data = image.load()
    for y in range(0, h):
        for x in range(0, w):
            r, g, b = data[x, y]
            if r > 200 and g < 90 and b < 60:
                xs.append(x)
                ys.append(y)
    if not xs:
        return 0, None
    return len(xs), (sum(xs) / len(xs), sum(ys) / len(ys))


def severe_entries(driver):
    return [e for e in driver.get_log("browser") if e.get("level") == "SEVERE"]


def read_trace(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def live_case(sear, work, env, robots, profile):
    """Checks 1-4 on one live run of the test project."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.support.ui import Select
    # 12 s of sim: long enough for every live check at real time, short enough to end by itself
    # so that the traces are complete when we read them.
    project = write_project(os.path.join(work, "live"), 12, robots)
    out = os.path.join(work, "live-out")
    # Without --start the run waits at t = 0 for Space: the page's own start, and no race with a
    # browser that takes long to come up on a loaded machine.
    viewer = Viewer([sear, "view", project, "--port", "0", "-o", out], env)
    driver = browser(profile)
    try:
        driver.get(viewer.url + "?camera=top")
        wait_for("first frame", lambda: int(dataset(driver, "frames") or 0) >= 1, 30)
        check(float(dataset(driver, "simTime") or -1) == 0, "1. waits at t = 0 (%s)" % dataset(driver, "simTime"))
        wait_for("the start hint", lambda: dataset(driver, "state") == "waiting", 10)
        hint = driver.find_element("id", "status").text
        check("press Space or Start" in hint, "1. the held start says what to do (%r)" % hint)
        ActionChains(driver).send_keys(" ").perform()
        wait_for("frames", lambda: int(dataset(driver, "frames") or 0) > 5, 10)
        check(dataset(driver, "mode") == "live", "1. hello says live mode (mode=%s)" % dataset(driver, "mode"))
        check(int(dataset(driver, "frames") or 0) > 5, "1. page draws frames (%s)" % dataset(driver, "frames"))
        severe = severe_entries(driver)
        check(not severe, "1. no SEVERE console entries on load %s" % severe)

        # 2. Not blank, and the scripted robot's pixels move on the top-down camera.
        first = canvas_shot(driver)
        colours = len(set(first.getdata()))
        most = max(n for n, _ in first.getcolors(first.size[0] * first.size[1]))
        # A blank view is one clear colour. The top view of this flat world is mostly one
        # green, but its grid lines, wall and robots cover some 5 % of it: 1 % is well below.
        check(colours >= 20 and most < 0.99 * first.size[0] * first.size[1],
              "2. screenshot not blank (%d colours, commonest covers %.1f %%)" %
              (colours, 100.0 * most / (first.size[0] * first.size[1])))
        n1, c1 = robot_pixels(first)
        time.sleep(1.0)
        n2, c2 = robot_pixels(canvas_shot(driver))
        # At 0.8 duty the rover rolls at about 0.5 m/s (0.754 m/s no-load wheel speed, 160 rpm on
        # 45 mm wheels): ~0.5 m in 1 s, tens of pixels at the top view's scale (~80 px/m); 5 px
        # is well above the jitter of an antialiased edge.
        check(n1 >= 20 and n2 >= 20, "2. robot found by its colour (%d, %d px)" % (n1, n2))
        if c1 and c2:
            moved = ((c1[0] - c2[0]) ** 2 + (c1[1] - c2[1]) ** 2) ** 0.5
            check(moved > 5, "2. robot's pixels moved %.1f px in 1 s" % moved)
        # Its path (0xff8c1a) is drawn behind it: over ~0.5 m at ~80 px/m, some 40 px of a line a
        # pixel or two wide. No other colour of the scene has that red with that much green.
        trail = path_pixels(canvas_shot(driver))
        check(trail >= 20, "2. the robot's path is drawn behind it (%d px)" % trail)

        # 3. Keys drive the robot with no MCU: one press of U (no auto-repeat from Selenium) sets
        # 0.25 duty (kDutyPerPress, tools/view/view_session.cpp), which stays after the release.
        Select(driver.find_element("id", "keyrobot")).select_by_value("driven")
        t_key = float(dataset(driver, "simTime"))
        ActionChains(driver).key_down("u").pause(1.5).key_up("u").perform()
        t_key_end = float(dataset(driver, "simTime"))

        # 4. Pause holds sim time; resume lets it run on.
        driver.find_element("id", "pause").click()
        wait_for("paused", lambda: dataset(driver, "state") == "paused", 3)
        held = dataset(driver, "simTime")
        time.sleep(1.0)
        still = dataset(driver, "simTime")
        check(dataset(driver, "state") == "paused" and held == still,
              "4. paused: sim time held (%s -> %s)" % (held, still))
        driver.find_element("id", "resume").click()
        wait_for("running", lambda: float(dataset(driver, "simTime")) > float(still) + 0.3, 3)
        check(float(dataset(driver, "simTime")) > float(still) + 0.3,
              "4. resumed: sim time runs on (%s -> %s)" % (still, dataset(driver, "simTime")))

        ended = wait_for("ended", lambda: dataset(driver, "state") == "ended", 15)
        check(ended, "the live run ends at its duration (state %s)" % dataset(driver, "state"))
        severe = severe_entries(driver)
        check(not severe, "1. no SEVERE console entries during the run %s" % severe)
    finally:
        driver.quit()
        viewer.stop()

    trace = os.path.join(out, "trace_driven.csv")
    if not check(os.path.exists(trace), "3. trace of the key-driven robot written (%s)" % trace):
        return
    rows = read_trace(trace)
    x0 = float(rows[0]["x_m"])
    before = [float(r["x_m"]) for r in rows if float(r["time_s"]) <= t_key]
    after = [float(r["x_m"]) for r in rows if float(r["time_s"]) >= t_key_end + 0.5]
    # At rest the robot only settles (2 mm in 3 s here). U drives it forward (+x, it faces east):
    # 0.25 duty of the 0.754 m/s no-load wheel speed (160 rpm, 45 mm wheels) is ~0.19 m/s, so
    # from the press to 0.5 s after the release (2 s) it covers ~0.3 m even counting the
    # spin-up; 5 cm is far above settling and far below that.
    rest = max(abs(x - x0) for x in before) if before else 0
    check(rest < 0.02, "3. driven robot at rest before the key (moved %.3f m)" % rest)
    if check(bool(after), "3. trace runs past the key press"):
        check(max(after) - x0 > 0.05, "3. key U moved the robot %.3f m forward" % (max(after) - x0))


def replay_case(sear, work, env, robots, profile):
    """Check 5: a replay file of a 2 s run opens with its timeline."""
    project = write_project(os.path.join(work, "replay"), 2, robots)
    replay = os.path.join(work, "run.replay.gz")
    run = subprocess.run([sear, "run", project, "--replay", replay, "-d", "2", "-q", "-o", os.path.join(work, "replay-out")],
                         env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
    if not check(run.returncode == 0 and os.path.exists(replay), "5. sear run --replay wrote %s (exit %d)" %
                 (replay, run.returncode)):
        print(run.stdout)
        return
    viewer = Viewer([sear, "view", "--replay", replay, "--port", "0"], env)
    driver = browser(profile)
    try:
        driver.get(viewer.url + "?camera=top")
        wait_for("replay", lambda: float(driver.execute_script(
            "return document.getElementById('timeline').max") or 0) > 0, 10)
        check(dataset(driver, "mode") == "replay", "5. hello says replay mode (mode=%s)" % dataset(driver, "mode"))
        top = float(driver.execute_script("return document.getElementById('timeline').max") or 0)
        # Frames every 1/20 s (the default replay rate): the last is at the run's end, 2 s.
        check(abs(top - 2.0) <= 0.05 + 1e-9, "5. timeline max %.3f = the run's 2 s" % top)
        driver.execute_script("var t = document.getElementById('timeline'); t.value = '1';"
                              "t.dispatchEvent(new Event('input'));")
        shown = float(wait_for("scrub", lambda: dataset(driver, "simTime") if abs(
            float(dataset(driver, "simTime") or -1) - 1.0) <= 0.05 + 1e-9 else None, 3) or -1)
        check(abs(shown - 1.0) <= 0.05 + 1e-9, "5. scrubbed to the middle: frame at t=%.3f s shown" % shown)
        severe = severe_entries(driver)
        check(not severe, "5. no SEVERE console entries in replay %s" % severe)
    finally:
        driver.quit()
        viewer.stop()


HILLS_PROJECT = """<project name="viewer_hills">
  <run duration="30" seed="1" trace_rate="50"/>
  <world step="0.001">
    <terrain type="heightmap" image="{assets}/heightmaps/hills.png" size="40 40" min_height="0"
             max_height="1.2"/>
  </world>
  <robot file="{assets}/robots/rover.xml" name="probe">
    <pose x="0" y="0"/>
    <mcu name="main"><firmware executable="{ir_probe}"/><gp2d12 name="ir" adc="0" pos="0.15 0 0.02"/></mcu>
  </robot>
</project>
"""

# The lows' green and the tops' near-white of the page's height colours (heightColour in
# tools/view/page/world.js: 0.20 0.45 0.18 at the bottom, 0.90 0.90 0.88 at the top), as lit.
def terrain_shades(image):
    w, h = image.size
    data = image.load()
    green = light = 0
    for y in range(0, h - 40, 2):  # above the legend; every other pixel is plenty
        for x in range(0, w, 2):
            r, g, b = data[x, y]
            if g > r + 25 and g > b + 25:
                green += 1
            elif r > 150 and g > 150 and b > 110 and b <= r:
                light += 1  # pale browns to near-white; the sky's light blue has more blue than red
    return green, light


def plot_pixels(driver):
    """Pixels of the readings plot drawn by its lines: right of the value labels and below the
    title, anything brighter than its #111 background."""
    return driver.execute_script(
        "var c = document.querySelector('canvas.plot');"
        "if (!c || c.hidden) return -1;"
        "var d = c.getContext('2d').getImageData(60, 14, c.width - 60, c.height - 14).data, n = 0;"
        "for (var i = 0; i < d.length; i += 4) if (d[i] + d[i + 1] + d[i + 2] > 3 * 60) n++;"
        "return n;")


def hills_case(sear, work, env, assets, ir_probe, profile):
    """Check 6: hills show on the terrain (coloured by height), and a clicked readings row is drawn
    as a live plot that grows frame by frame."""
    folder = os.path.join(work, "hills")
    os.makedirs(folder)
    project = os.path.join(folder, "project.xml")
    with open(project, "w") as f:
        f.write(HILLS_PROJECT.format(assets=assets, ir_probe=ir_probe))
    viewer = Viewer([sear, "view", project, "--port", "0", "-o", os.path.join(work, "hills-out")], env)
    driver = browser(profile)
    try:
        driver.get(viewer.url + "?camera=top")
        wait_for("first frame", lambda: int(dataset(driver, "frames") or 0) >= 1, 30)
        shot = canvas_shot(driver)
        green, light = terrain_shades(shot)
        # The top camera frames the whole 40 m heightmap. hills.png's valleys cover about a tenth of
        # the view and its hill tops (the upper third of the height range) some 2 % (counted at every
        # other pixel: ~115 000 samples). 1 % and 0.5 % are well below what is drawn, and a terrain
        # of one colour, flat or unlit, has none of one or the other.
        samples = shot.size[0] * shot.size[1] // 4
        check(green > 0.01 * samples and light > 0.005 * samples,
              "6. hills show: %d green lows and %d light tops of %d samples" % (green, light, samples))
        from selenium.webdriver.common.action_chains import ActionChains
        ActionChains(driver).send_keys(" ").perform()
        row = wait_for("a readings row", lambda: driver.find_elements("css selector", "table.readings tr[data-device]"), 20)
        if not check(bool(row), "6. the probe's readings are listed"):
            return
        # Readings say what they are in words and units (the GP2D12's output in volts), not as raw
        # field names; the world's colours have a legend.
        table = driver.find_element("css selector", "table.readings").text
        check("output voltage (V)" in table and "_" not in table,
              "6. readings named with units (%r)" % table[:120])
        page = driver.execute_script("return document.body.innerText")
        check("IR / sonar beam" in page and "robot's path" in page, "6. the legend names the world's colours")
        # The row is found, checked to be what a pointer at its middle would hit, and clicked in one
        # script: between a WebDriver click's finding the row and its pointer landing, the page can
        # redraw and grow the logs above it (CI saw the click miss that way).
        hit = driver.execute_script(
            "var row = document.querySelector('table.readings tr[data-device]');"
            "row.scrollIntoView({block: 'center'});"
            "var r = row.getBoundingClientRect();"
            "var top = document.elementFromPoint((r.left + r.right) / 2, (r.top + r.bottom) / 2);"
            "if (!top || !row.contains(top)) return 'covered by ' + (top ? top.outerHTML.slice(0, 80) : 'nothing');"
            "top.click();"
            "return 'clicked';")
        if not check(hit == "clicked", "6. a readings row can be clicked (%s)" % hit):
            return
        first = wait_for("plot", lambda: plot_pixels(driver) > 0 and plot_pixels(driver), 10)
        # One point a frame, one pixel apart (PLOT_POINTS 300 on a 300 px canvas): a second at the
        # page's 20 frames a second lengthens each line by ~20 px; 5 is above the redraw's jitter.
        # A loaded host sends fewer frames a second, so the wait is for the growth, not for a second.
        later = wait_for("plot grows", lambda: plot_pixels(driver) > (first or 0) + 5 and plot_pixels(driver), 10)
        later = later if later else plot_pixels(driver)
        check(first > 0 and later > first + 5,
              "6. the clicked row is plotted live (%s then %d px of line)" % (first, later))
    finally:
        driver.quit()
        viewer.stop()


def main():
    if len(sys.argv) not in (2, 3):
        print(__doc__)
        return 2
    sear = os.path.abspath(sys.argv[1])
    ir_probe = os.path.abspath(sys.argv[2]) if len(sys.argv) == 3 else None
    missing = missing_tools()
    if missing:
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            print("FAIL missing under CI: " + ", ".join(missing))
            return 1
        print("SKIP missing: " + ", ".join(missing))
        return SKIP
    robots = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "assets", "robots")
    env = dict(os.environ, SEAR_NO_PLOTS="1")
    work = tempfile.mkdtemp(prefix="sear-viewer-")
    started = time.time()
    try:
        live_case(sear, work, env, os.path.abspath(robots), os.path.join(work, "profile-live"))
        replay_case(sear, work, env, os.path.abspath(robots), os.path.join(work, "profile-replay"))
        if ir_probe:
            hills_case(sear, work, env, os.path.abspath(os.path.join(robots, "..")), ir_probe,
                       os.path.join(work, "profile-hills"))
    except Exception as e:  # a case that could not even run is a failure, with its reason
        check(False, "%s: %s" % (type(e).__name__, e))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("%d failure(s) in %.1f s" % (len(failures), time.time() - started))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
