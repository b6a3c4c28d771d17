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
    this.latest = null;
    this.dropped = 0;
    this.lastSeq = -1;
  }

  Panel.prototype.clearLogs = function () {
    this.console.textContent = "";
    this.wire.textContent = "";
    this.dropped = 0;
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

  Panel.prototype.takeFrame = function (m) {
    this.latest = m;
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
      if (p) p.takeFrame(m);
    });
  };

  SEAR.Panels.prototype.clear = function () {
    var self = this;
    Object.keys(this.panels).forEach(function (id) { self.panels[id].clearLogs(); self.panels[id].latest = null; });
  };

  SEAR.Panels.prototype.render = function () {
    var self = this;
    Object.keys(this.panels).forEach(function (id) { self.panels[id].render(); });
  };

  SEAR.Panels.MAX_LINES = MAX_LINES;
})();
