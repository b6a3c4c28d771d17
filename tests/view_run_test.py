#!/usr/bin/python3
"""`sear run --view`, `sear view` and replay files end to end, through python3-websocket: frames
after hello and scene, pause/step/resume, Start, reset, keyboard driving, pages that misbehave,
and that a page watching changes nothing the run writes.

Usage: view_run_test.py SEAR IR_PROBE ASSET_DIR
"""
import gzip
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import unittest
import urllib.request

import websocket

SEAR, IR_PROBE, ASSETS = sys.argv[1:4]
del sys.argv[1:4]
STEP_S = 0.001


def project(duration_s):
    """A rover with no MCU (`driver`, driven by keys) and one whose MCU runs the IR probe."""
    rover = os.path.join(ASSETS, "robots", "rover.xml")
    return f"""<project name="viewtest">
  <run duration="{duration_s}" seed="3" trace_rate="100"/>
  <world step="{STEP_S}"><terrain type="flat"/></world>
  <robot name="driver" file="{rover}"><pose x="0" y="0"/></robot>
  <robot name="probe" file="{rover}"><pose x="0" y="3"/>
    <mcu name="main"><firmware executable="{IR_PROBE}"/><gp2d12 name="ir" adc="0" pos="0.15 0 0.02"/></mcu>
  </robot>
</project>
"""


class Sear:
    """A `sear` process whose stderr is collected; its viewer's address once printed."""

    def __init__(self, args, cwd):
        self.proc = subprocess.Popen([SEAR] + args, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                     text=True)
        self.err = []
        self.address = None
        seen = threading.Event()

        def drain():
            for line in self.proc.stderr:
                self.err.append(line)
                m = re.search(r"sear: viewer on http://([^/]+)/", line)
                if m and not self.address:
                    self.address = m.group(1)
                    seen.set()
            seen.set()

        self.thread = threading.Thread(target=drain, daemon=True)
        self.thread.start()
        seen.wait(60)

    def stderr(self):
        self.thread.join(5)
        return "".join(self.err)

    def wait(self, timeout=60):
        return self.proc.wait(timeout)

    def page(self):
        return Page(self.address)


class Page:
    """A WebSocket client reading the viewer's messages."""

    def __init__(self, address):
        self.ws = websocket.create_connection(f"ws://{address}/ws", timeout=10)

    def recv(self):
        return json.loads(self.ws.recv())

    def send(self, **command):
        self.ws.send(json.dumps(command))

    def until(self, predicate, timeout=20):
        """Messages until one satisfies `predicate`; that one."""
        deadline = time.time() + timeout
        while time.time() < deadline:
            m = self.recv()
            if predicate(m):
                return m
        raise AssertionError("no such message in time")

    def statuses_for(self, seconds):
        """Every status that arrives within `seconds` of wall time."""
        got, deadline = [], time.time() + seconds
        self.ws.settimeout(0.05)
        while time.time() < deadline:
            try:
                m = json.loads(self.ws.recv())
            except websocket.WebSocketTimeoutException:
                continue
            if m["type"] == "status":
                got.append(m)
        self.ws.settimeout(10)
        return got

    def close(self):
        self.ws.close()


def read_bytes(path):
    with open(path, "rb") as f:
        return f.read()


def trace(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
        return [dict(zip(header, line.strip().split(","))) for line in f if line.strip()]


def raw_websocket(address, rcvbuf=0):
    host, port = address.rsplit(":", 1)
    s = socket.socket()
    if rcvbuf:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, rcvbuf)
    s.connect((host, int(port)))
    s.sendall(f"GET /ws HTTP/1.1\r\nHost: {address}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
              "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n".encode())
    head = b""
    while b"\r\n\r\n" not in head:
        head += s.recv(1)
    assert b" 101 " in head, head
    return s


class ViewRun(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="sear_view_run_")
        self.addCleanup(shutil.rmtree, self.dir, True)

    def project_file(self, duration_s, name="p.xml"):
        path = os.path.join(self.dir, name)
        with open(path, "w") as f:
            f.write(project(duration_s))
        return path

    def test_frames_follow_hello_and_scene_and_their_time_grows(self):
        sear = Sear(["run", self.project_file(3), "--view", "--port", "0", "--realtime", "1", "-q", "-o", "out"],
                    self.dir)
        self.assertIsNotNone(sear.address)
        page = sear.page()
        hello = page.recv()
        self.assertEqual((hello["type"], hello["mode"], hello["project"]), ("hello", "live", "viewtest"))
        self.assertEqual(hello["step_s"], STEP_S)
        self.assertEqual(page.recv()["type"], "scene")
        times = []
        while len(times) < 10:
            m = page.recv()
            if m["type"] == "frame":
                times.append(m["t"])
        self.assertEqual(times, sorted(set(times)), "each frame later than the one before")
        page.close()
        self.assertEqual(sear.wait(), 0, sear.stderr())

    def test_pause_holds_time_step_advances_exactly_n_steps_and_resume_goes_on(self):
        sear = Sear(["run", self.project_file(20), "--view", "--port", "0", "--realtime", "1", "-q", "-o", "out"],
                    self.dir)
        page = sear.page()
        page.until(lambda m: m["type"] == "status" and m["t"] > 0.1)
        page.send(cmd="pause")
        held = page.until(lambda m: m["type"] == "status" and m["paused"])
        later = page.statuses_for(0.4)  # ≥ 200 ms of wall time: the sim clock must not move
        self.assertTrue(all(s["t"] == held["t"] for s in later), (held, later))
        page.send(cmd="speed", factor=0)  # a status, also while held
        self.assertEqual(page.until(lambda m: m["type"] == "status")["t"], held["t"])
        page.send(cmd="step", n=25)
        stepped = page.until(lambda m: m["type"] == "status" and m["paused"] and m["t"] != held["t"])
        self.assertAlmostEqual(stepped["t"], held["t"] + 25 * STEP_S, delta=1e-9)
        self.assertTrue(all(s["t"] == stepped["t"] for s in page.statuses_for(0.3)))
        page.send(cmd="resume")  # at speed 0: to the end at once
        end = page.until(lambda m: m["type"] == "status" and m["ended"], timeout=60)
        self.assertAlmostEqual(end["t"], 20, delta=1e-9)
        self.assertEqual(sear.wait(), 0, sear.stderr())

    def test_a_crawling_speed_still_answers_at_once_and_ctrl_c_ends_it(self):
        sear = Sear(["run", self.project_file(20), "--view", "--port", "0", "--realtime", "1", "-q", "-o", "out"],
                    self.dir)
        page = sear.page()
        page.until(lambda m: m["type"] == "status" and m["t"] > 0.05)
        # 1e-6 would hold each 1 ms step for 17 minutes: ignored. 0.001, the slowest taken, holds
        # each for a second of wall time; the run still answers every command within a few
        # 5 ms slices. The bound is the step itself: a run that slept a whole step before reading
        # commands would take up to 1 s; 0.9 s leaves a loaded or sanitized host all the slack.
        page.send(cmd="speed", factor=1e-6)
        page.send(cmd="speed", factor=0.001)
        self.assertEqual(page.until(lambda m: m["type"] == "status" and m["speed"] != 1, timeout=5)["speed"], 0.001)
        time.sleep(0.05)  # early in a step's second: a whole-step sleep would answer after ~0.95 s
        sent = time.time()
        page.send(cmd="pause")
        held = page.until(lambda m: m["type"] == "status" and m["paused"], timeout=5)
        self.assertLess(time.time() - sent, 0.9)
        sent = time.time()
        page.send(cmd="resume")
        page.until(lambda m: m["type"] == "status" and not m["paused"], timeout=5)
        self.assertLess(time.time() - sent, 0.9)
        time.sleep(0.2)  # inside the next step's second again
        sear.proc.send_signal(signal.SIGINT)
        self.assertEqual(sear.wait(timeout=5), 128 + signal.SIGINT, sear.stderr())
        self.assertLess(held["t"], 0.2)  # it did crawl: at 0.001x the run barely moved

    def test_pages_that_leave_mid_frame_or_stop_reading_do_not_stop_the_run(self):
        sear = Sear(["run", self.project_file(3), "--view", "--port", "0", "--realtime", "1.5", "-q", "-o", "out"],
                    self.dir)
        leaving = raw_websocket(sear.address)
        stuck = raw_websocket(sear.address, rcvbuf=1024)
        leaving.recv(300)  # part of the hello and scene
        time.sleep(0.3)
        leaving.recv(100)
        leaving.close()
        self.assertEqual(sear.wait(), 0, sear.stderr())
        stuck.close()
        with open(os.path.join(self.dir, "out", "summary.json")) as f:
            summary = json.load(f)
        self.assertEqual(summary["status"], "completed")
        self.assertAlmostEqual(summary["sim_time_s"], 3, delta=1e-9)

    def test_a_page_watching_changes_nothing_the_run_writes(self):
        p = self.project_file(2)
        sear = Sear(["run", p, "--view", "--port", "0", "--realtime", "2", "-q", "-o", "watched", "--replay",
                     "watched.gz"], self.dir)
        page = sear.page()
        frames = 0
        try:
            while True:
                frames += page.recv()["type"] == "frame"
        except (websocket.WebSocketException, ConnectionError):
            pass
        self.assertEqual(sear.wait(), 0, sear.stderr())
        self.assertGreater(frames, 10)  # ~20 a second over the run's second of wall time
        subprocess.run([SEAR, "run", p, "-q", "-o", "alone", "--replay", "alone.gz"], cwd=self.dir, check=True)
        for name in ("watched/trace_driver.csv", "watched/trace_probe.csv", "watched/sensors_probe.csv",
                     "watched.gz"):
            alone = name.replace("watched", "alone")
            self.assertEqual(read_bytes(os.path.join(self.dir, name)), read_bytes(os.path.join(self.dir, alone)), name)

    def test_keys_drive_the_robot_without_an_mcu_and_are_refused_once_for_one_with(self):
        sear = Sear(["run", self.project_file(3), "--view", "--port", "0", "--realtime", "1", "-q", "-o", "out"],
                    self.dir)
        page = sear.page()
        page.until(lambda m: m["type"] == "status" and m["t"] > 0.2)
        for _ in range(4):  # 4 x 0.25: full duty
            page.send(cmd="key", key="u", down=True, robot="driver")
            page.send(cmd="key", key="u", down=False, robot="driver")
        page.send(cmd="key", key="ArrowUp", down=True, robot="probe")
        page.send(cmd="key", key="ArrowUp", down=True, robot="probe")
        page.until(lambda m: m["type"] == "status" and m["t"] > 1.5)
        page.send(cmd="key", key="h", down=True, robot="driver")
        page.until(lambda m: m["type"] == "status" and m["t"] > 2.0)
        page.send(cmd="key", key="h", down=False, robot="driver")
        self.assertEqual(sear.wait(), 0, sear.stderr())
        driver = trace(os.path.join(self.dir, "out", "trace_driver.csv"))
        probe = trace(os.path.join(self.dir, "out", "trace_probe.csv"))
        # At full duty the 160 rpm gearmotors on 45 mm wheels roll at up to 0.75 m/s: over the
        # ~1.3 s straight before H, well over 0.5 m even with the start-up and the turn's slowing.
        x = [float(r["x_m"]) for r in driver]
        self.assertGreater(x[-1] - x[20], 0.5)
        # H held ~0.5 s: left side at half duty, right at full: (0.75 - 0.375) / 0.22 m track
        # = 1.7 rad/s counter-clockwise, so the yaw grows by far more than 0.3 rad.
        self.assertGreater(float(driver[-1]["yaw_rad"]), 0.3)
        self.assertLess(abs(float(probe[-1]["x_m"]) - float(probe[0]["x_m"])), 0.01)
        self.assertEqual(sear.stderr().count("robot 'probe' has an MCU"), 1, sear.stderr())

    def test_a_view_stopped_before_its_end_keeps_to_its_own_folder(self):
        """Without --out, `sear run` writes sear-out/viewtest/ and `sear view` sear-out/viewtest.view/:
        a view ended with Ctrl-C while it waits for Start leaves the completed run as it was."""
        p = self.project_file(0.2)
        subprocess.run([SEAR, "run", p, "-q"], cwd=self.dir, check=True)
        sear = Sear(["view", p, "--port", "0", "-q"], self.dir)
        self.assertIsNotNone(sear.address, sear.stderr())
        sear.proc.send_signal(signal.SIGINT)
        code = sear.wait()
        err = sear.stderr()
        sear.proc.stderr.close()
        self.assertEqual(code, 130, err)
        out = os.path.join(self.dir, "sear-out")
        with open(os.path.join(out, "viewtest", "summary.json")) as f:
            self.assertEqual(json.load(f)["status"], "completed")
        with open(os.path.join(out, "viewtest.view", "summary.json")) as f:
            self.assertEqual(json.load(f)["status"], "interrupted")
        self.assertEqual(os.readlink(os.path.join(out, "latest")), "viewtest.view")

    def test_view_waits_for_start_keeps_serving_after_the_end_and_resets(self):
        sear = Sear(["view", self.project_file(1), "--port", "0", "-q", "-o", "out"], self.dir)
        page = sear.page()
        waiting = page.statuses_for(0.4)
        self.assertTrue(waiting and all(s["t"] == 0 and s["paused"] and s["waiting"] for s in waiting), waiting)
        self.assertEqual(waiting[-1]["reason"], "press Space or Start to begin")
        page.send(cmd="speed", factor=0)
        page.send(cmd="start")
        ended = page.until(lambda m: m["type"] == "status" and m["ended"])
        self.assertFalse(ended["waiting"])
        time.sleep(0.3)
        self.assertIsNone(sear.proc.poll(), "sear view stays after the run")
        page.send(cmd="key", key="Enter", down=True)
        page.until(lambda m: m["type"] == "scene")
        page.until(lambda m: m["type"] == "status" and m["ended"])  # at speed 0 again
        sear.proc.send_signal(signal.SIGINT)
        self.assertEqual(sear.wait(), 0, sear.stderr())
        self.assertIn("reset by the viewer", sear.stderr())

    def test_a_page_opened_late_gets_the_console_lines_said_before_it(self):
        sear = Sear(["view", self.project_file(5), "--port", "0", "-q", "-o", "out"], self.dir)
        first = sear.page()
        first.send(cmd="speed", factor=0)
        first.send(cmd="start")
        first.until(lambda m: m["type"] == "status" and not m["paused"])
        first.close()  # from here on no page watches, until the second comes
        # The run's end is when its summary is written (sear view then keeps serving): only then
        # does the late page come, so that most of the run had no page watching it.
        summary = os.path.join(self.dir, "out", "summary.json")
        deadline = time.time() + 60
        while not os.path.exists(summary) and time.time() < deadline:
            time.sleep(0.05)
        late = sear.page()
        frame = late.until(lambda m: m["type"] == "frame")
        probe = next(m for m in frame["mcus"] if m["id"] == "probe.main")
        lines = [e for e in probe["log"] if e["kind"] == "console"]
        # The IR probe prints a line after each 100 ms delay and four 104 us conversions (plus a
        # few 3.125 us HAL calls): one every 100.42 ms, each ending when its last byte is out
        # (86.8 us a byte at 115200, so a digit more or less moves it by that). Every line since
        # the first is there, none missing, and the last is less than a period before the
        # frame's time, the late page coming at the run's end (50 lines; a frame holds 400).
        self.assertGreater(len(lines), 0)
        self.assertEqual([e["seq"] for e in lines], list(range(len(lines))), lines)
        self.assertAlmostEqual(lines[0]["t"], 0.1 + 4 * 104e-6 + 13 * 86.8e-6, delta=0.0005)
        gaps = [b["t"] - a["t"] for a, b in zip(lines, lines[1:])]
        self.assertTrue(all(abs(g - 0.10042) < 0.0003 for g in gaps), gaps)
        self.assertLess(frame["t"] - lines[-1]["t"], 0.10042 + 0.0003, (frame["t"], lines[-1]))
        self.assertTrue(lines[0]["text"].startswith("adc "), lines[0])
        self.assertAlmostEqual(frame["t"], 5, delta=1e-9)
        late.close()
        sear.proc.send_signal(signal.SIGINT)
        self.assertEqual(sear.wait(), 0, sear.stderr())

    def test_a_short_run_waits_for_its_first_page_and_keeps_its_end_on_show(self):
        # Half a second at full speed is over in a few tens of milliseconds, before a browser is
        # up; --view-wait holds it at t = 0 until a page comes, --view-keep serves its end.
        sear = Sear(["run", self.project_file(0.5), "--view", "--view-wait", "60", "--view-keep", "--port", "0",
                     "-q", "-o", "out"], self.dir)
        page = sear.page()
        first = page.until(lambda m: m["type"] == "frame")
        self.assertEqual(first["t"], 0, "the run waited for the page")
        end = page.until(lambda m: m["type"] == "status" and m["ended"])
        self.assertAlmostEqual(end["t"], 0.5, delta=1e-9)
        self.assertIsNone(sear.proc.poll(), "the run's end stays on show")
        page.close()
        sear.proc.send_signal(signal.SIGINT)
        self.assertEqual(sear.wait(), 0, sear.stderr())

    def test_garbage_from_a_page_harms_neither_the_run_nor_the_next_page(self):
        sear = Sear(["run", self.project_file(1), "--view", "--view-wait", "60", "--view-keep", "--realtime", "1",
                     "--port", "0", "-q", "-o", "out"], self.dir)
        bad = sear.page()
        bad.ws.send_binary(b"\x00\xff" * 1000)
        bad.ws.send("x" * (10 * 1024 * 1024))
        for text in ["{", "[" * 100000, "{" * 100000, '{"cmd":"step","n":NaN}', '{"cmd":"step","n":-5}',
                     '{"cmd":"step","n":1e300}', '{"cmd":"speed","factor":NaN}', '{"cmd":"speed","factor":-1}',
                     '{"cmd":"speed","factor":1e308}', '"cmd"', "null", '{"cmd":"key","key":"' + "k" * 5000 + '"}',
                     '{"cmd":"key","key":"h","down":"yes","robot":42}']:
            bad.ws.send(text)
        # The resets go first: behind the burst they could find the queue of 1024 waiting commands
        # full (a slow host, a sanitizer build) and be dropped, as documented.
        for _ in range(100):
            bad.send(cmd="reset")
        for i in range(5000):
            bad.send(cmd="speed", factor=1 + i % 2)
        bad.send(cmd="speed", factor=1)
        bad.close()
        good = sear.page()
        self.assertEqual(good.recv()["type"], "hello")
        # The resets start the run over; whatever the burst did, it reaches its 1 s end at real time.
        end = good.until(lambda m: m["type"] == "status" and m["ended"], timeout=120)
        self.assertAlmostEqual(end["t"], 1, delta=1e-9)
        good.close()
        sear.proc.send_signal(signal.SIGINT)
        self.assertEqual(sear.wait(), 0, sear.stderr())
        self.assertIn("reset by the viewer", sear.stderr())

    def test_replay_files_hold_hello_scene_and_a_frame_every_period_identically(self):
        p = self.project_file(1)
        for name in ("a", "b"):
            subprocess.run([SEAR, "run", p, "-q", "-o", name, "--replay", name + ".gz", "--replay-rate", "20"],
                           cwd=self.dir, check=True)
        a, b = (read_bytes(os.path.join(self.dir, n)) for n in ("a.gz", "b.gz"))
        self.assertEqual(a, b)
        lines = [json.loads(line) for line in gzip.decompress(a).decode().splitlines()]
        self.assertEqual((lines[0]["type"], lines[0]["mode"]), ("hello", "replay"))
        self.assertEqual(lines[1]["type"], "scene")
        times = [m["t"] for m in lines[2:]]
        self.assertTrue(all(m["type"] == "frame" for m in lines[2:]))
        self.assertEqual(len(times), 21)  # t = 0, 0.05, ... 1.0
        for i, t in enumerate(times):
            self.assertAlmostEqual(t, i * 0.05, delta=1e-9)

    def test_an_avr_mcu_shows_its_cpu_load_and_a_native_one_none(self):
        firmware = os.path.join(os.path.dirname(os.path.abspath(__file__)), "avr", "firmware", "timer1_sleep.c")
        p = os.path.join(self.dir, "avr.xml")
        with open(p, "w") as f:
            f.write(project(0.5).replace(
                '<robot name="driver" file="{0}"><pose x="0" y="0"/></robot>'.format(
                    os.path.join(ASSETS, "robots", "rover.xml")),
                '<robot name="driver" file="{0}"><pose x="0" y="0"/><mcu name="main" engine="avr">'
                '<firmware sources="{1}"/></mcu></robot>'.format(os.path.join(ASSETS, "robots", "rover.xml"),
                                                                  firmware)))
        run = subprocess.run([SEAR, "run", p, "-q", "-o", "out", "--replay", "r.gz", "--replay-rate", "20"],
                             cwd=self.dir, stderr=subprocess.PIPE, text=True)
        self.assertEqual(run.returncode, 0, run.stderr)
        frames = [json.loads(line) for line in gzip.decompress(read_bytes(os.path.join(self.dir, "r.gz"))).decode()
                  .splitlines()[2:]]
        loads = {m["id"]: [] for m in frames[-1]["mcus"]}
        for frame in frames:
            for m in frame["mcus"]:
                loads[m["id"]].append((frame["t"], m["cpu_load"]))
        # The native engine cannot tell.
        self.assertTrue(all(load is None for _, load in loads["probe.main"]), loads["probe.main"])
        # The chip sleeps but for the timer's ISR, once every 16000 cycles: entry, a prologue and
        # epilogue of a few pushes and pops, one store, RETI, well under 80 cycles, so under 0.5 %
        # busy and never 0. A load is shown once its first 100 ms window is over.
        avr = [load for t, load in loads["driver.main"] if t >= 0.1 + 1e-9]
        self.assertTrue(avr and all(load is not None and 0 < load < 0.005 for load in avr), loads["driver.main"])
        self.assertTrue(all(load is None for t, load in loads["driver.main"] if t < 0.1 - 1e-9))

    def test_view_replay_serves_the_file_and_refuses_what_is_not_one(self):
        p = self.project_file(0.5)
        subprocess.run([SEAR, "run", p, "-q", "-o", "o", "--replay", "r.gz"], cwd=self.dir, check=True)
        sear = Sear(["view", "--replay", "r.gz", "--port", "0"], self.dir)
        page = sear.page()
        hello = page.recv()
        self.assertEqual((hello["type"], hello["mode"]), ("hello", "replay"))
        with urllib.request.urlopen(f"http://{sear.address}/replay") as r:
            self.assertEqual(r.headers["Content-Encoding"], "gzip")
            self.assertEqual(r.read(), read_bytes(os.path.join(self.dir, "r.gz")))
        page.close()
        sear.proc.send_signal(signal.SIGINT)
        self.assertEqual(sear.wait(), 0)
        with open(os.path.join(self.dir, "plain.txt"), "w") as f:
            f.write('{"type":"hello"}\n')
        for name, why in (("missing.gz", "no such replay file"), ("plain.txt", "not a replay file")):
            r = subprocess.run([SEAR, "view", "--replay", name, "--port", "0"], cwd=self.dir, capture_output=True,
                               text=True, timeout=30)
            self.assertEqual(r.returncode, 1)
            self.assertIn(f"{name}: {why}", r.stderr)

    def test_a_second_viewer_on_a_taken_port_is_refused_clearly(self):
        first = Sear(["view", "--replay", self.make_replay(), "--port", "0"], self.dir)
        port = first.address.rsplit(":", 1)[1]
        r = subprocess.run([SEAR, "run", self.project_file(0.1), "--view", "--port", port, "-q", "-o", "x"],
                           cwd=self.dir, capture_output=True, text=True, timeout=60)
        first.proc.send_signal(signal.SIGINT)
        first.wait()
        self.assertEqual(r.returncode, 1)
        self.assertIn(f"127.0.0.1 port {port}", r.stderr)
        self.assertIn("--port", r.stderr)

    def make_replay(self):
        subprocess.run([SEAR, "run", self.project_file(0.1, "short.xml"), "-q", "-o", "short", "--replay", "short.gz"],
                       cwd=self.dir, check=True)
        return "short.gz"


if __name__ == "__main__":
    unittest.main(verbosity=2)
