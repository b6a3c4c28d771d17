// One panel per MCU: console, pins and PWM/servo, readings against truth, and the UART/CAN log.
// The logs keep their last MAX_LINES lines so a long run does not grow the page without bound.
"use strict";
var SEAR = window.SEAR || (window.SEAR = {});

(function () {
  var MAX_LINES = 500;

  function el(tag, cls, text) {
    var e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function fmt(v) {
    if (typeof v !== "number") return String(v);
    if (!isFinite(v)) return v > 0 ? "inf" : (v < 0 ? "-inf" : "nan");
    var a = Math.abs(v);
    if (a !== 0 && (a < 1e-3 || a >= 1e5)) return v.toExponential(3);
    return v.toFixed(a >= 100 ? 1 : 3);
  }

  // SI units as the frames carry them, shown at the scale the parts' datasheets use: a field in
  // µT (the Earth's is some 50), angles in degrees.
  var SHOWN = {
    "T": { unit: "µT", scale: 1e6 },
    "rad": { unit: "°", scale: 180 / Math.PI },
    "rad/s": { unit: "°/s", scale: 180 / Math.PI },
    "1": { unit: "", scale: 1 }
  };
  function shown(unit) { return SHOWN[unit] || { unit: unit || "", scale: 1 }; }

  function appendBounded(box, line) {
    var stick = box.scrollTop + box.clientHeight >= box.scrollHeight - 4;
    box.appendChild(line);
    while (box.childNodes.length > MAX_LINES) box.removeChild(box.firstChild);
    if (stick) box.scrollTop = box.scrollHeight;
  }

  function Panel(desc) {
    this.id = desc.id;
    this.root = el("section", "mcu");
    this.root.id = "mcu-" + desc.id.replace(/[^A-Za-z0-9_-]/g, "_");
    var head = el("h3", null, desc.id);
    this.state = el("span", "mcu-state", "");
    head.appendChild(this.state);
    this.root.appendChild(head);
    var units = this.units = {};
    (desc.devices || []).forEach(function (d) { units[d.name] = d.units || {}; });
    var devices = (desc.devices || []).map(function (d) { return d.name + " (" + d.element + ", " + d.wiring + ")"; });
    if (devices.length) this.root.appendChild(el("div", "devices", devices.join(" · ")));
    this.pins = el("div", "pins");
    this.root.appendChild(this.pins);
    // Each part folds away, so that a long table does not push the logs out of sight.
    var self = this;
    function part(title, child) {
      var d = el("details");
      d.open = true;
      d.appendChild(el("summary", null, title));
      d.appendChild(child);
      self.root.appendChild(d);
      return child;
    }
    this.console = part("console", el("div", "log console"));
    this.wire = part("UART / CAN", el("div", "log wire"));
    this.readings = part("readings and truth", el("table", "readings"));
    // A row clicked in the table is drawn over time here: the reading against its truth.
    this.plot = el("canvas", "plot");
    this.plot.width = 300;
    this.plot.height = 80;
    this.plot.hidden = true;
    this.readings.parentNode.appendChild(this.plot);
    this.plotted = null;  // {device, quantity, points: [[t, reading, truth]]}
    this.readings.addEventListener("click", function (ev) {
      var row = ev.target.closest("tr");
      if (!row || !row.dataset.device) return;
      self.plotted = { device: row.dataset.device, quantity: row.dataset.quantity, points: [] };
      self.plot.hidden = false;
    });
    this.latest = null;
    this.dropped = 0;
    this.lastSeq = -1;
  }

  Panel.prototype.clearLogs = function () {
    this.console.textContent = "";
    this.wire.textContent = "";
    this.dropped = 0;
    if (this.plotted) this.plotted.points = [];  // a reset starts the run, and its plot, over
  };

  Panel.prototype.addEntry = function (e) {
    // A page that connects gets the recent log in its first frame; so do the pages already
    // watching, which have those entries: the numbers tell.
    if (typeof e.seq === "number") {
      if (e.seq <= this.lastSeq) return;
      this.lastSeq = e.seq;
    }
    var stamp = (typeof e.t === "number" ? e.t.toFixed(3) : "") + " ";
    if (e.kind === "console") {
      appendBounded(this.console, el("div", null, stamp + e.text));
      return;
    }
    var line = el("div", "entry " + e.kind);
    var label = e.kind + (e.dir ? " " + e.dir : "") + (e.device ? " " + e.device : "") + (e.bus !== undefined ? " " + e.bus : "");
    line.appendChild(el("span", "tag", stamp + label + " "));
    var text = e.text !== undefined ? e.text : e.hex;
    if (e.kind === "lms" && e.crc_ok === false) text += "  (bad CRC)";
    line.appendChild(el("span", null, text));
    if (e.hex) line.title = e.hex;
    appendBounded(this.wire, line);
  };

  var PLOT_POINTS = 300;  // one a frame: 15 s of wall time at 20 frames a second

  Panel.prototype.takeFrame = function (m, t) {
    this.latest = m;
    var p = this.plotted;
    if (p) {
      var r = ((m.readings || {})[p.device] || {})[p.quantity], tr = ((m.truth || {})[p.device] || {})[p.quantity];
      p.points.push([t, typeof r === "number" ? r : null, typeof tr === "number" ? tr : null]);
      if (p.points.length > PLOT_POINTS) p.points.shift();
    }
    this.dropped += m.dropped || 0;
    var self = this;
    (m.log || []).forEach(function (e) { self.addEntry(e); });
  };

  // Tables are redrawn at most a few times a second, from the newest frame.
  Panel.prototype.render = function () {
    var m = this.latest;
    if (!m) return;
    var waiting = SEAR.view && SEAR.view.waiting;
    this.state.textContent = (m.running ? (waiting ? " ready, waiting for Start" : " running")
                                        : " stopped" + (m.stopped ? ": " + m.stopped : "")) +
                             (typeof m.cpu_load === "number" ? " · CPU " + (100 * m.cpu_load).toFixed(1) + " %" : "") +
                             (this.dropped ? " · " + this.dropped + " log entries dropped" : "");
    this.state.className = "mcu-state " + (m.running ? "ok" : "bad");
    var pins = this.pins;
    pins.textContent = "";
    Object.keys(m.pins || {}).forEach(function (p) {
      pins.appendChild(el("span", "pin " + (m.pins[p] ? "high" : "low"), p));
    });
    Object.keys(m.pwm || {}).forEach(function (p) {
      pins.appendChild(el("span", "pwm", "pwm " + p + ": " + m.pwm[p] + " (" + Math.round(m.pwm[p] / 2.55) + " %)"));
    });
    Object.keys(m.servo || {}).forEach(function (p) {
      pins.appendChild(el("span", "pwm", "servo " + p + ": " + m.servo[p] + " µs"));
    });
    var table = this.readings, readings = m.readings || {}, truth = m.truth || {};
    table.textContent = "";
    var devices = Object.keys(readings);
    Object.keys(truth).forEach(function (d) { if (devices.indexOf(d) < 0) devices.push(d); });
    if (!devices.length) return;
    var head = el("tr");
    ["device", "quantity", "reading", "truth"].forEach(function (h) { head.appendChild(el("th", null, h)); });
    table.appendChild(head);
    var units = this.units;
    devices.forEach(function (d) {
      var qs = Object.keys(readings[d] || {});
      Object.keys(truth[d] || {}).forEach(function (q) { if (qs.indexOf(q) < 0) qs.push(q); });
      qs.forEach(function (q) {
        var row = el("tr");
        row.dataset.device = d;
        row.dataset.quantity = q;
        row.title = "click: draw it over time";
        var u = shown((units[d] || {})[q]);
        row.appendChild(el("td", null, d));
        row.appendChild(el("td", null, q.replace(/_/g, " ") + (u.unit ? " (" + u.unit + ")" : "")));
        var r = (readings[d] || {})[q], t = (truth[d] || {})[q];
        function value(v) { return v === undefined ? "" : (v === null ? "–" : fmt(typeof v === "number" ? v * u.scale : v)); }
        row.appendChild(el("td", "num", value(r)));
        row.appendChild(el("td", "num", value(t)));
        table.appendChild(row);
      });
    });
  };

  // The chosen reading (orange) and its truth (white) over the last frames, scaled to fit.
  Panel.prototype.drawPlot = function () {
    var p = this.plotted;
    if (!p || this.plot.hidden) return;
    var u = shown((this.units[p.device] || {})[p.quantity]);
    var c = this.plot.getContext("2d"), w = this.plot.width, h = this.plot.height;
    c.fillStyle = "#111";
    c.fillRect(0, 0, w, h);
    var lo = Infinity, hi = -Infinity;
    p.points.forEach(function (q) {
      [q[1], q[2]].forEach(function (v) { if (v !== null) { lo = Math.min(lo, v); hi = Math.max(hi, v); } });
    });
    c.fillStyle = "#ccc";
    c.font = "10px sans-serif";
    c.fillText(p.device + " " + p.quantity.replace(/_/g, " ") + (u.unit ? " (" + u.unit + ")" : "") +
               ": reading (orange), truth (white)", 4, 11);
    if (!(hi >= lo)) return;
    if (hi === lo) { hi += 1; lo -= 1; }
    c.fillText(fmt(hi * u.scale), 4, 22);
    c.fillText(fmt(lo * u.scale), 4, h - 3);
    [[1, "#ff8c1a"], [2, "#ffffff"]].forEach(function (line) {
      c.strokeStyle = line[1];
      c.beginPath();
      var drawing = false;
      p.points.forEach(function (q, i) {
        var v = q[line[0]];
        if (v === null) { drawing = false; return; }
        var x = w * i / PLOT_POINTS, y = h - 4 - (h - 18) * (v - lo) / (hi - lo);
        if (drawing) c.lineTo(x, y); else c.moveTo(x, y);
        drawing = true;
      });
      c.stroke();
    });
  };

  SEAR.Panels = function (container) {
    this.container = container;
    this.panels = {};
  };

  SEAR.Panels.prototype.build = function (scene) {
    var self = this;
    this.container.textContent = "";
    this.panels = {};
    (scene.robots || []).forEach(function (r) {
      (r.mcus || []).forEach(function (desc) {
        var p = new Panel(desc);
        self.panels[desc.id] = p;
        self.container.appendChild(p.root);
      });
    });
    if (!Object.keys(this.panels).length) this.container.appendChild(el("p", "none", "No MCU in this project."));
  };

  SEAR.Panels.prototype.takeFrame = function (frame) {
    var self = this;
    (frame.mcus || []).forEach(function (m) {
      var p = self.panels[m.id];
      if (p) p.takeFrame(m, frame.t);
    });
  };

  SEAR.Panels.prototype.clear = function () {
    var self = this;
    Object.keys(this.panels).forEach(function (id) { self.panels[id].clearLogs(); self.panels[id].latest = null; });
  };

  SEAR.Panels.prototype.render = function () {
    var self = this;
    Object.keys(this.panels).forEach(function (id) { self.panels[id].render(); self.panels[id].drawPlot(); });
  };

  SEAR.Panels.MAX_LINES = MAX_LINES;
})();
