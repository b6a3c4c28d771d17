#!/usr/bin/env python3
"""A URDF robot's visuals in the browser viewer (issue 24), headless chromium: the diffbot's blue
chassis mesh (rgba 0.15 0.3 0.7 from its URDF) shows as blue pixels on the top-down camera, where a
robot drawn without its visuals is the viewer's own red box.

Usage: urdf_viewer_test.py SEAR_BINARY   (exit 0 pass, 1 fail, 77 skip)
"""
import os
import shutil
import sys
import tempfile
import time

sys.dont_write_bytecode = True  # no __pycache__ beside the sources
import viewer_test as v  # noqa: E402  (its helpers: the viewer process, the browser, screenshots)

# The diffbot alone, no MCU or script: it stands still at the origin of a small flat world.
PROJECT = """<project name="urdf_viewer_test">
  <run duration="5" seed="1"/>
  <world step="0.001">
    <wall name="east" from="1.5 -1" to="1.5 1" height="0.2" thickness="0.1"/>
  </world>
  <robot name="diffbot" urdf="{urdf}">
    <package name="diffbot" dir="{assets}"/>
    <wheel name="left" joint="left_wheel_joint"/>
    <wheel name="right" joint="right_wheel_joint"/>
    <caster link="caster_link"/>
  </robot>
</project>
"""


def blue_pixels(image):
    """The chassis's blue, lit or shaded: blue well above red and green. The ground's greens and
    browns, the grey wall and the black wheels each fail it; above the bottom 40 px, where the
    legend shows the LIDAR's cyan and the GPS fixes' blue."""
    data = image.load()
    w, h = image.size
    return sum(1 for y in range(h - 40) for x in range(w)
               if data[x, y][2] > 90 and data[x, y][2] > data[x, y][0] + 50 and data[x, y][2] > data[x, y][1] + 25)


def blue_pixels_of(sear, env, work, name, urdf, assets):
    """`sear view` of the diffbot from `urdf`, on the top camera at t = 0: its blue pixels."""
    project = os.path.join(work, name, "project.xml")
    os.makedirs(os.path.dirname(project), exist_ok=True)
    with open(project, "w") as f:
        f.write(PROJECT.format(urdf=urdf, assets=assets))
    viewer = v.Viewer([sear, "view", project, "--port", "0", "-o", os.path.join(work, name, "out")], env)
    driver = v.browser(os.path.join(work, name, "profile"))
    try:
        driver.get(viewer.url + "?camera=top")
        v.wait_for("first frame", lambda: int(v.dataset(driver, "frames") or 0) >= 1, 30)
        v.check(not v.severe_entries(driver), "%s: no SEVERE console entries on load" % name)
        return blue_pixels(v.canvas_shot(driver))
    finally:
        driver.quit()
        viewer.stop()


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    sear = os.path.abspath(sys.argv[1])
    missing = v.missing_tools()
    if missing:
        if os.environ.get("CI", "").lower() in ("1", "true", "yes"):
            print("FAIL missing under CI: " + ", ".join(missing))
            return 1
        print("SKIP missing: " + ", ".join(missing))
        return v.SKIP
    assets = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "assets"))
    env = dict(os.environ, SEAR_NO_PLOTS="1")
    work = tempfile.mkdtemp(prefix="sear-urdf-viewer-")
    started = time.time()
    try:
        # The diffbot as published, and a copy whose blue is red: the blue pixels are the URDF's.
        with open(os.path.join(assets, "robots", "diffbot.urdf")) as f:
            urdf = f.read()
        red = os.path.join(work, "red", "diffbot.urdf")
        os.makedirs(os.path.dirname(red))
        with open(red, "w") as f:
            f.write(urdf.replace('rgba="0.15 0.3 0.7 1"', 'rgba="0.7 0.15 0.1 1"'))
        blue = blue_pixels_of(sear, env, work, "blue", os.path.join(assets, "robots", "diffbot.urdf"), assets)
        reddened = blue_pixels_of(sear, env, work, "red", red, assets)
        # The chassis is 0.3 x 0.18 m: on this top view (some 130 px a metre) about 40 x 24 px, 900
        # of them blue. 50 is well above any stray antialiased edge; recoloured, it has none.
        v.check(blue >= 50, "the URDF chassis is drawn in its own blue (%d px)" % blue)
        v.check(reddened < 5, "the same chassis coloured red in its URDF leaves no blue (%d px)" % reddened)
    except Exception as e:  # a case that could not even run is a failure, with its reason
        v.check(False, "%s: %s" % (type(e).__name__, e))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("%d failure(s) in %.1f s" % (len(v.failures), time.time() - started))
    return 1 if v.failures else 0


if __name__ == "__main__":
    sys.exit(main())
