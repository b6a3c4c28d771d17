#!/usr/bin/python3
"""Plots of one finished SEAR run, drawn from its output folder with matplotlib (Debian's
python3-matplotlib): `plot_run.py OUT_DIR` writes OUT_DIR/plot_*.png, each 1200 x 900 px.

  plot_trajectory_ROBOT.png        the path over a top view of the terrain's heights and the
                                   obstacles (world.json), collisions marked (summary.json)
  plot_motors_ROBOT.png            motor duties, wheel speeds (and servo pulses) from trace_ROBOT.csv
  plot_sensor_ROBOT.MCU.DEV.png    per sensor: for a model in the firmware's process, the truth it
                                   measured and the reading it gave the firmware (sensors_ROBOT.csv),
                                   on the same axes where they are the same quantity, in panels of
                                   their own where not (an IR ranger's volts, with the ADC code the
                                   firmware read beside them, an echo's width, an encoder's count);
                                   for a GPS, the fixes the firmware received (NMEA in
                                   ROBOT.MCU.uartN.log) against the trace's position

Cheap by design, as every run draws them: matplotlib's figures without pyplot on Agg, no
tight_layout (fixed margins), every series thinned to a few points per pixel column, PNGs written
with light compression. Each PNG appears whole (written aside, then renamed into place).
Exits 0 when every plot was written; otherwise its last line says what went wrong (sear prints it).
"""

import csv
import json
import math
import os
import sys

# Fixed size, so that a viewer or a CI page shows every run alike.
WIDTH_IN, HEIGHT_IN, DPI = 12, 9, 100
# Colours the tests look for in the pixels: the path, the collision marks, the truth and the reading.
PATH_COLOUR = "#e6007e"
COLLISION_COLOUR = "#ff0000"
TRUTH_COLOUR = "#1f77b4"
READING_COLOUR = "#ff7f0e"

NO_ECHO_COLOUR = "#7f7f7f"

GPS_ELEMENTS = ("ublox_neo6m", "mtk3339")
# Rangers whose output the firmware reads on an ADC pin.
ADC_RANGERS = ("gp2d12", "maxbotix_lv_ez")
# An HC-SR04 that heard no echo drops ECHO after its 38 ms time-out (hal/devices/hcsr04.h,
# HCSR04_NO_ECHO_NS), which a firmware would read as 6.55 m, beyond the part's 4 m. An echo from
# 4 m lasts 23.2 ms; any width from 30 ms on is the time-out, whatever the timing resolution.
HCSR04_NO_ECHO_S = 0.030

# What the sensors CSV's quantities mean, for the axes: a label, the unit shown, the factor from
# the CSV's SI value to it.
QUANTITIES = {
    "distance": ("distance", "m", 1), "range": ("range", "in", 1),
    "output_voltage": ("output voltage", "V", 1), "output_level": ("output level", "0 low, 1 high", 1),
    "echo_width": ("echo pulse width", "ms", 1e3), "closed": ("switch", "0 open, 1 closed", 1),
    "count": ("encoder count", "edges", 1), "shaft_angle": ("shaft angle", "rad", 1),
    "shaft_rate": ("shaft speed", "rad/s", 1),
}
for _axis in "xyz":
    QUANTITIES[f"specific_force_{_axis}"] = (f"specific force {_axis}", "m/s²", 1)
    QUANTITIES[f"angular_rate_{_axis}"] = (f"angular rate {_axis}", "rad/s", 1)
    QUANTITIES[f"field_{_axis}"] = (f"magnetic field {_axis}", "µT", 1e6)  # the Earth's reads better in µT


def quantity_label(quantity, unit):
    """(axis label with its unit, factor from the CSV's value): a quantity not in the table keeps
    its name and unit."""
    label, shown, scale = QUANTITIES.get(quantity, (quantity.replace("_", " "), unit, 1))
    return (f"{label} ({shown})" if shown and shown != "1" else label), scale


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def read_trace(path):
    """Columns by name as lists of floats (text cells, as motor modes, are left out); a row cut short
    by a killed run is skipped."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    names = rows[0]
    columns = {n: [] for n in names}
    numeric = set(names)
    for row in rows[1:]:
        if len(row) != len(names):
            continue
        try:
            float(row[0])
        except ValueError:
            continue
        for n, cell in zip(names, row):
            if n not in numeric:
                continue
            try:
                columns[n].append(float(cell))
            except ValueError:
                numeric.discard(n)
    return {n: columns[n] for n in names if n in numeric}


def figure(rows=1, cols=1, right=0.97, **kw):
    """A figure of the fixed size with its panels; fixed margins rather than tight_layout, which
    took a quarter of the drawing time."""
    from matplotlib.figure import Figure
    fig = Figure(figsize=(WIDTH_IN, HEIGHT_IN), dpi=DPI)
    axes = fig.subplots(rows, cols, squeeze=False, **kw)
    fig.subplots_adjust(left=0.08, right=right, bottom=0.07, top=0.9, hspace=0.3, wspace=0.3)
    return fig, [a for line in axes for a in line]


def save(fig, out_dir, name):
    # No bbox_inches="tight": it would change the image's size. Light compression: zlib's default
    # level took a tenth of the drawing time for files a third smaller. Written aside and renamed,
    # so that a PNG in the folder is always whole.
    path = os.path.join(out_dir, name)
    fig.savefig(path + ".part", dpi=DPI, format="png", pil_kwargs={"compress_level": 1})
    os.replace(path + ".part", path)


def thin(t, v, columns):
    """The points of a series worth drawing across `columns` pixels: per run of samples that fall
    in one column, the first, the lowest, the highest and the first not finite (a gap), in time
    order; a short series is left alone. Lines drawn from it look the same at this size."""
    import numpy as np
    n = len(v)
    per = n // columns
    if per < 4:
        return t, v
    rows = n // per
    block = np.asarray(v[:rows * per], dtype=float).reshape(rows, per)
    finite = np.isfinite(block)
    base = np.arange(rows) * per
    keep = [base, base + np.where(finite, block, np.inf).argmin(axis=1),
            base + np.where(finite, block, -np.inf).argmax(axis=1)]
    gapped = ~finite.all(axis=1)
    keep.append((base + (~finite).argmax(axis=1))[gapped])
    keep.append(np.arange(rows * per, n))
    index = np.unique(np.concatenate(keep))
    return [t[i] for i in index], [v[i] for i in index]


def legend_outside(ax):
    """The legend right of the panel, where it hides no data."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9, borderaxespad=0)


def interp(t, times, values):
    import numpy as np
    return float(np.interp(t, times, values))


# --- trajectory over the world -------------------------------------------------------------------

def rectangle(cx, cy, length, width, yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    corners = [(length / 2, width / 2), (-length / 2, width / 2), (-length / 2, -width / 2), (length / 2, -width / 2)]
    return [(cx + c * x - s * y, cy + s * x + c * y) for x, y in corners]


def draw_terrain(ax, fig, world):
    import numpy as np
    terrain = (world or {}).get("terrain", {})
    grid = terrain.get("heights_m")
    if terrain.get("kind") in ("heightmap", "mesh") and grid:
        heights = np.array([[np.nan if v is None else v for v in row] for row in grid], dtype=float)
        cx, cy = terrain.get("center_m", [0, 0])
        sx, sy = terrain["size_m"]
        image = ax.imshow(np.ma.masked_invalid(heights), extent=[cx - sx / 2, cx + sx / 2, cy - sy / 2, cy + sy / 2],
                          origin="upper", cmap="gist_earth", interpolation="bilinear", zorder=0)
        fig.colorbar(image, ax=ax, label="terrain height (m)", shrink=0.8)
        return (cx - sx / 2, cx + sx / 2, cy - sy / 2, cy + sy / 2)
    ax.set_facecolor("#f4f4f0")
    return None


def draw_obstacles(ax, world):
    from matplotlib.patches import Circle, Polygon
    obstacles = (world or {}).get("obstacles", {})
    style = dict(facecolor="#8c6d46", edgecolor="black", linewidth=1, alpha=0.85, zorder=2)
    for b in obstacles.get("boxes", []):
        ax.add_patch(Polygon(rectangle(*b["center_m"], b["size_m"][0], b["size_m"][1], b["yaw_rad"]), closed=True,
                             **dict(style, hatch="//" if b.get("movable") else None)))
        ax.annotate(b["name"], b["center_m"], fontsize=8, ha="center", va="center", zorder=5)
    for w in obstacles.get("walls", []):
        (x0, y0), (x1, y1) = w["from_m"], w["to_m"]
        length = math.hypot(x1 - x0, y1 - y0)
        ax.add_patch(Polygon(rectangle((x0 + x1) / 2, (y0 + y1) / 2, length, w["thickness_m"],
                                       math.atan2(y1 - y0, x1 - x0)), closed=True, **dict(style, facecolor="#9a3b26")))
    for t in obstacles.get("trees", []):
        ax.add_patch(Circle(t["center_m"], t["crown_radius_m"], facecolor="#2e8b57", alpha=0.25, edgecolor="#2e8b57",
                            linestyle="--", zorder=1))
        ax.add_patch(Circle(t["center_m"], t["trunk_radius_m"], **dict(style, facecolor="#5b3a1e")))
        ax.annotate(t["name"], t["center_m"], xytext=(0, -12), textcoords="offset points", fontsize=8, ha="center",
                    zorder=5)
    for m in obstacles.get("meshes", []):
        if len(m["footprint_m"]) >= 3:
            ax.add_patch(Polygon(m["footprint_m"], closed=True, **dict(style, facecolor="#7f7f7f")))
        else:
            ax.plot(*m["center_m"], marker="s", color="#7f7f7f", zorder=2)
        ax.annotate(m["name"], m["center_m"], fontsize=8, ha="center", va="center", zorder=5)


def plot_trajectory(out_dir, robot, trace, world, summary):
    fig, (ax,) = figure()
    extent = draw_terrain(ax, fig, world)
    draw_obstacles(ax, world)
    t, x, y = trace["time_s"], trace["x_m"], trace["y_m"]
    stride = max(1, len(x) // (4 * WIDTH_IN * DPI))  # a path of a few points a pixel looks the same
    ax.plot(x[::stride] + [x[-1]], y[::stride] + [y[-1]], color=PATH_COLOUR, linewidth=2.5, label=f"{robot}'s path", zorder=3)
    ax.plot(x[0], y[0], marker="o", markersize=10, color=PATH_COLOUR, markeredgecolor="black", label="start",
            linestyle="none", zorder=4)
    ax.plot(x[-1], y[-1], marker="s", markersize=10, color=PATH_COLOUR, markeredgecolor="black",
            label=f"end, t = {t[-1]:.2f} s", linestyle="none", zorder=4)
    hits = [c for c in (summary or {}).get("collision_events", []) if robot in (c.get("robot"), c.get("other"))]
    for i, c in enumerate(hits):
        cx, cy = interp(c["time_s"], t, x), interp(c["time_s"], t, y)
        other = c["other"] if c.get("robot") == robot else c.get("robot")
        ax.plot(cx, cy, marker="X", markersize=14, color=COLLISION_COLOUR, markeredgecolor="black", linestyle="none",
                label="collision" if i == 0 else None, zorder=6)
        ax.annotate(f"{c['time_s']:.2f} s: {other}", (cx, cy), xytext=(8, 8), textcoords="offset points",
                    fontsize=9, color="black", zorder=6,
                    bbox=dict(boxstyle="round", facecolor="white", alpha=0.8))
    # The path with a margin, within the terrain: obstacles far from the robot are not the point.
    span = max(max(x) - min(x), max(y) - min(y), 1.0)
    margin = max(3.0, 0.25 * span)
    x0, x1, y0, y1 = min(x) - margin, max(x) + margin, min(y) - margin, max(y) + margin
    if extent:
        x0, x1, y0, y1 = max(x0, extent[0]), min(x1, extent[1]), max(y0, extent[2]), min(y1, extent[3])
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x east (m)")
    ax.set_ylabel("y north (m)")
    terrain = ((world or {}).get("terrain") or {}).get("kind", "unknown")
    ax.set_title(f"{robot}: path over the {terrain} terrain, {len(hits)} collision(s)")
    ax.legend(loc="upper right", fontsize=9)
    ax.grid(True, alpha=0.3)
    save(fig, out_dir, f"plot_trajectory_{robot}.png")


# --- motors and wheels ---------------------------------------------------------------------------

def plot_motors(out_dir, robot, trace):
    t = trace["time_s"]
    groups = [("motor_", "_duty", "duty (signed, + forward)"), ("wheel_", "_radps", "wheel speed (rad/s)"),
              ("servo_", "_pulse_us", "servo pulse (µs)")]
    panels = [(g, [n for n in trace if n.startswith(g[0]) and n.endswith(g[1])]) for g in groups]
    panels = [p for p in panels if p[1]]
    if not panels:
        return False
    fig, axes = figure(len(panels), 1, right=0.88, sharex=True)
    for ax, ((prefix, suffix, label), names) in zip(axes, panels):
        for n in names:
            ax.plot(*thin(t, trace[n], WIDTH_IN * DPI), linewidth=1.5, label=n[len(prefix):-len(suffix)])
        ax.set_ylabel(label)
        legend_outside(ax)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("sim time (s)")
    axes[0].set_title(f"{robot}: motor commands and wheel speeds")
    save(fig, out_dir, f"plot_motors_{robot}.png")
    return True


# --- sensors -------------------------------------------------------------------------------------

def read_sensors(path):
    """{(mcu, device): {source: {(quantity, unit): ([t], [v])}}} in file order; source "truth" or
    "reading" (a file without the source column holds truth only)."""
    devices = {}
    with open(path, newline="") as f:
        rows = csv.reader(f)
        header = next(rows, [])
        has_source = len(header) > 6
        for row in rows:
            if len(row) < 6:
                continue  # a line cut short by a killed run
            try:
                t, v = float(row[0]), float(row[5])
            except ValueError:
                continue
            source = (row[6] if has_source and len(row) > 6 else "") or "truth"
            series = devices.setdefault((row[1], row[2]), {}).setdefault(source, {}).setdefault((row[3], row[4]),
                                                                                                 ([], []))
            series[0].append(t)
            series[1].append(v)
    return devices


def device_of(world, robot, mcu, device):
    """(the MCU, the device) as world.json describes them, or (None, None)."""
    for r in (world or {}).get("robots", []):
        if r["name"] == robot:
            for m in r["mcus"]:
                if m["name"] == mcu:
                    for d in m["devices"]:
                        if d["name"] == device:
                            return m, d
    return None, None


def fit_readings(ax, truth, reading):
    """Scales the y axis to the truth and the bulk of the readings when a few readings lie far off
    (further from the bulk than its own span): a device's registers read 0 until the firmware wakes
    it, which would otherwise squash an IMU's 9.81 m/s^2 or a field's tens of uT to a line. Returns
    how many readings it left off the axis."""
    truth = [x for x in truth if math.isfinite(x)]
    finite = sorted(x for x in reading if math.isfinite(x))
    if not truth or len(finite) < 20:
        return 0
    cut = len(finite) // 100 + 1  # the extreme 1 % of each end, at least one
    core = truth + finite[cut:len(finite) - cut]
    lo, hi = min(core), max(core)
    span = (hi - lo) or abs(hi) or 1.0
    near = [x for x in finite if lo - span <= x <= hi + span]
    if len(near) == len(finite):
        return 0
    lo, hi = min(truth + near), max(truth + near)
    pad = 0.05 * ((hi - lo) or abs(hi) or 1.0)
    ax.set_ylim(lo - pad, hi + pad)
    return len(finite) - len(near)


def no_echo_times(element, reading):
    """The times an HC-SR04 heard nothing (its echo the 38 ms time-out), from its echo widths."""
    if element != "hcsr04":
        return set()
    widths = reading.get(("echo_width", "s"))
    return {t for t, w in zip(*widths) if w >= HCSR04_NO_ECHO_S} if widths else set()


def plot_measured(out_dir, robot, mcu, device, element, sources, avcc_v=None):
    """One panel per quantity: the truth and the reading on the same axes where they share it (an
    IMU's axes, a compass's field, a sonar's distance, an encoder's angle); a reading of another
    quantity (an IR ranger's volts, an echo's width, a count) gets a panel of its own below, on the
    same time axis, rather than a twin y axis over the truth that would hide one or the other. An
    ADC ranger's volts get the code the firmware read on a second axis (10 bits against AVCC); an
    HC-SR04's time-outs are drawn as "no echo" marks and gaps, not as the 6.55 m they would read."""
    truth, reading = sources.get("truth", {}), sources.get("reading", {})
    panels = list(truth) + [key for key in reading if key not in truth]
    n = len(panels)
    rows = min(n, 3)
    cols = (n + rows - 1) // rows
    fig, axes = figure(rows, cols, sharex=True)
    times = [x for series in list(truth.values()) + list(reading.values()) for x in series[0]]
    t_end = max(times)
    columns = WIDTH_IN * DPI // cols
    silent = no_echo_times(element, reading)
    handles = {}
    for ax, key in zip(axes, panels):
        quantity, unit = key
        label, scale = quantity_label(quantity, unit)
        drawn = []
        for series, colour, name, width in ((truth.get(key), TRUTH_COLOUR, "truth measured", 2.5),
                                            (reading.get(key), READING_COLOUR, "reading given the firmware", 1.5)):
            if not series:
                continue
            is_reading = series is reading.get(key)
            v = [x * scale for x in series[1]]
            if is_reading and silent and quantity == "distance":
                v = [math.nan if t in silent else x for t, x in zip(series[0], v)]
            # A reading holds until the next: drawn on to the end of the run.
            t = series[0] + ([t_end] if is_reading else [])
            v_drawn = v + ([v[-1]] if is_reading else [])
            t, v_drawn = thin(t, v_drawn, columns)
            (line,) = ax.step(t, v_drawn, where="post", color=colour, linewidth=width, label=name)
            handles.setdefault(name, line)
            drawn.extend(x for x in v if not math.isnan(x))
        if silent and quantity == "distance" and key in reading:
            gone = sorted(silent)
            marks = ax.plot(gone, [0.97] * len(gone), linestyle="none", marker="v", markersize=6,
                            color=NO_ECHO_COLOUR, transform=ax.get_xaxis_transform(), clip_on=False,
                            label="no echo (the 38 ms time-out)")
            handles.setdefault("no echo", marks[0])
        def scaled(source):  # what is drawn, time-outs left out
            if key not in source:
                return []
            return [x * scale for t, x in zip(*source[key])
                    if not (source is reading and quantity == "distance" and t in silent)]

        off_scale = fit_readings(ax, scaled(truth), scaled(reading))
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.set_xlim(min(times), max(t_end, min(times) + 1e-3))  # an infinite value is not drawn, nor scaled to
        if drawn and all(math.isinf(x) for x in drawn):
            ax.text(0.5, 0.5, "nothing in range for the whole run", transform=ax.transAxes, ha="center", fontsize=12)
        elif any(math.isinf(x) for x in drawn) or (silent and quantity == "distance"):
            ax.set_title("(gaps: nothing in range" + (", no echo" if silent else "") + ")", fontsize=9)
        elif off_scale:
            ax.set_title(f"({off_scale} reading(s) off scale, as the registers before the firmware set the part up)",
                         fontsize=9)
        ax.set_ylabel(label)
        if element in ADC_RANGERS and quantity == "output_voltage" and avcc_v:
            # What the firmware read: analogRead's code, Vin x 1024 / Vref (hal/include/hal/adc.h).
            codes = ax.secondary_yaxis("right", functions=(lambda v: v * 1024 / avcc_v, lambda c: c * avcc_v / 1024))
            codes.set_ylabel(f"ADC code read (10 bits, AVCC = {avcc_v:g} V)")
        ax.grid(True, alpha=0.3)
    for ax in axes[n:]:
        ax.set_visible(False)
    for ax in axes[-cols:]:
        ax.set_xlabel("sim time (s)")
    said = "the truth its model measured (blue) and the reading it gave the firmware (orange)" if reading else \
        "the truth its model measured; no reading reached the firmware"
    fig.suptitle(f"{robot}.{mcu}.{device} ({element}): {said}")
    # One legend for every panel, above them, where it hides no data.
    fig.legend(list(handles.values()), [h.get_label() for h in handles.values()], loc="upper center",
               bbox_to_anchor=(0.5, 0.955), ncol=len(handles), fontsize=9, frameon=False)
    fig.subplots_adjust(right=0.92 if element in ADC_RANGERS else 0.97)
    save(fig, out_dir, f"plot_sensor_{robot}.{mcu}.{device}.png")


def uart_bytes(path):
    """(end-of-stop-bit time, byte) the MCU received, from a ROBOT.MCU.uartN.log capture."""
    out = []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if len(parts) == 3 and parts[1] == "rx":
                try:
                    out.append((float(parts[0]), int(parts[2], 16)))
                except ValueError:
                    pass
    return out


def nmea_fixes(received):
    """(time the sentence's last byte arrived, UTC time of day of the fix in s, latitude, longitude,
    altitude or None): the first valid GGA or RMC fix of each epoch with a good checksum."""
    fixes, sentence, epochs = [], None, set()
    for t, b in received:
        c = chr(b)
        if c == "$":
            sentence = ""
        elif sentence is not None and c == "\n":
            fix = parse_nmea(sentence.strip())
            if fix and fix[0] not in epochs:
                epochs.add(fix[0])
                fixes.append((t,) + fix)
            sentence = None
        elif sentence is not None:
            sentence += c
    return fixes


def time_of_day(hhmmss):
    return int(hhmmss[0:2]) * 3600 + int(hhmmss[2:4]) * 60 + float(hhmmss[4:])


def parse_nmea(body):
    if "*" not in body:
        return None
    data, checksum = body.rsplit("*", 1)
    total = 0
    for ch in data:
        total ^= ord(ch)
    try:
        if total != int(checksum[:2], 16):
            return None
    except ValueError:
        return None
    f = data.split(",")

    def angle(value, hemisphere, degree_digits):
        if not value:
            return None
        a = float(value[:degree_digits]) + float(value[degree_digits:]) / 60
        return -a if hemisphere in ("S", "W") else a

    try:
        if f[0][2:] == "GGA" and len(f) > 9 and f[6] not in ("", "0") and f[1]:
            lat, lon = angle(f[2], f[3], 2), angle(f[4], f[5], 3)
            return (time_of_day(f[1]), lat, lon, float(f[9]) if f[9] else None) if lat is not None and lon is not None else None
        if f[0][2:] == "RMC" and len(f) > 6 and f[2] == "A" and f[1]:
            lat, lon = angle(f[3], f[4], 2), angle(f[5], f[6], 3)
            return (time_of_day(f[1]), lat, lon, None) if lat is not None and lon is not None else None
    except ValueError:
        return None
    return None


def enu(origin, lat, lon, alt):
    """WGS-84 latitude, longitude, altitude -> east, north, up (m) from the world's GPS origin."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)

    def ecef(lat_deg, lon_deg, h):
        p, l = math.radians(lat_deg), math.radians(lon_deg)
        n = a / math.sqrt(1 - e2 * math.sin(p) ** 2)
        return ((n + h) * math.cos(p) * math.cos(l), (n + h) * math.cos(p) * math.sin(l), (n * (1 - e2) + h) * math.sin(p))

    p0, l0 = math.radians(origin["latitude_deg"]), math.radians(origin["longitude_deg"])
    x0 = ecef(origin["latitude_deg"], origin["longitude_deg"], origin["altitude_m"])
    x1 = ecef(lat, lon, alt)
    dx, dy, dz = (x1[i] - x0[i] for i in range(3))
    e = -math.sin(l0) * dx + math.cos(l0) * dy
    n = -math.sin(p0) * math.cos(l0) * dx - math.sin(p0) * math.sin(l0) * dy + math.cos(p0) * dz
    u = math.cos(p0) * math.cos(l0) * dx + math.cos(p0) * math.sin(l0) * dy + math.sin(p0) * dz
    return e, n, u


def plot_gps(out_dir, robot, mcu, device, trace, world):
    port = device["wires"].get("uart")
    log = os.path.join(out_dir, f"{robot}.{mcu}.uart{port}.log")
    if port is None or not os.path.exists(log):
        return False
    origin = world["gps_origin"]
    fixes = nmea_fixes(uart_bytes(log))
    t = trace["time_s"]
    # A fix is drawn at the sim time it is for (its UTC time less the receiver's utc_start), not
    # when its sentence arrived, which is later by the epoch's sentences at the baud rate.
    start = device.get("params", {}).get("utc_start", "")
    start_s = time_of_day(start[11:19].replace(":", "")) if len(start) >= 19 else None
    fig, axes = figure(3, 1, sharex=True)
    points = [enu(origin, lat, lon, alt if alt is not None else origin["altitude_m"]) for _, _, lat, lon, alt in fixes]
    ft = [(utc - start_s) % 86400 if start_s is not None else arrived for arrived, utc, _, _, _ in fixes]
    for i, (ax, column, label) in enumerate(zip(axes, ("x_m", "y_m"), ("east (m)", "north (m)"))):
        ax.plot(*thin(t, trace[column], WIDTH_IN * DPI), color=TRUTH_COLOUR, linewidth=1.5,
                label="truth (trace, chassis origin)")
        ax.plot(ft, [p[i] for p in points], linestyle="none", marker="o", markersize=5, color=READING_COLOUR,
                label="fix the firmware received (NMEA GGA/RMC)")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    # One legend, above the panels: inside one it hid the fixes behind it.
    fig.legend(*axes[0].get_legend_handles_labels(), loc="upper center", bbox_to_anchor=(0.5, 0.955), ncol=2,
               fontsize=9, frameon=False)
    errors = [math.hypot(p[0] - interp(s, t, trace["x_m"]), p[1] - interp(s, t, trace["y_m"])) for s, p in zip(ft, points)]
    axes[2].plot(ft, errors, linestyle="none", marker="o", markersize=5, color=READING_COLOUR)
    axes[2].set_ylabel("horizontal error (m)")
    axes[2].set_xlabel("sim time (s) of the fix" + ("" if start_s is not None else ", when its sentence arrived"))
    axes[2].grid(True, alpha=0.3)
    note = "" if fixes else ": no fix received"
    fig.suptitle(f"{robot}.{mcu}.{device['name']} ({device['element']}) on UART {port}{note}")
    save(fig, out_dir, f"plot_sensor_{robot}.{mcu}.{device['name']}.png")
    return True


# --- the run -------------------------------------------------------------------------------------

def robots_of(out_dir, world):
    names = [r["name"] for r in (world or {}).get("robots", [])]
    if not names:
        names = sorted(f[len("trace_"):-len(".csv")] for f in os.listdir(out_dir)
                       if f.startswith("trace_") and f.endswith(".csv"))
    return names


def main(argv):
    if len(argv) != 2 or not os.path.isdir(argv[1]):
        print("usage: plot_run.py OUT_DIR (a sear run's output folder)")
        return 2
    out_dir = argv[1]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.figure  # noqa: F401 (what every plot draws on)
    except ImportError:
        print("matplotlib is not installed (Debian: apt install python3-matplotlib)")
        return 2
    world = read_json(os.path.join(out_dir, "world.json"))
    summary = read_json(os.path.join(out_dir, "summary.json"))
    written, failed = [], []

    def attempt(name, draw, *args):
        try:
            if draw(*args) is not False:
                written.append(name)
        except Exception as e:  # one plot's trouble must not cost the others
            failed.append(f"{name}: {type(e).__name__}: {e}")

    for robot in robots_of(out_dir, world):
        trace_path = os.path.join(out_dir, f"trace_{robot}.csv")
        trace = read_trace(trace_path) if os.path.exists(trace_path) else {}
        if not trace.get("time_s"):
            failed.append(f"{robot}: no trace rows in {trace_path}")
            continue
        attempt(f"trajectory {robot}", plot_trajectory, out_dir, robot, trace, world, summary)
        attempt(f"motors {robot}", plot_motors, out_dir, robot, trace)
        sensors_path = os.path.join(out_dir, f"sensors_{robot}.csv")
        if os.path.exists(sensors_path):
            for (mcu, device), series in read_sensors(sensors_path).items():
                m, d = device_of(world, robot, mcu, device)
                # Without world.json's AVCC, the HAL's default (scene/description.hpp).
                attempt(f"sensor {robot}.{mcu}.{device}", plot_measured, out_dir, robot, mcu, device,
                        d["element"] if d else "?", series, (m or {}).get("avcc_v", 5.0))
        for r in (world or {}).get("robots", []):
            if r["name"] != robot:
                continue
            for m in r["mcus"]:
                for d in m["devices"]:
                    if d["element"] in GPS_ELEMENTS:
                        attempt(f"sensor {robot}.{m['name']}.{d['name']}", plot_gps, out_dir, robot, m["name"],
                                d, trace, world)
    for f in failed:
        print(f)
    if failed:
        print(f"{len(failed)} plot(s) failed, {len(written)} written; first: {failed[0]}")
        return 1
    log = os.path.join(out_dir, "plots.log")  # where sear puts what this prints: an empty one says nothing
    if os.path.exists(log) and os.path.getsize(log) == 0:
        os.remove(log)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
