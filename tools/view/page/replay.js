// Plays a replay file (the same messages as a live run) with a timeline to scrub. A reset inside
// the run starts a new segment; the timeline runs through the segments one after the other.
"use strict";
var SEAR = window.SEAR || (window.SEAR = {});

(function () {
  var MAX_SPEED = 20;  // "max" in a replay: as fast as is still worth watching

  function parse(text) {
    var messages = [];
    text.split("\n").forEach(function (line) {
      if (!line.trim()) return;
      try { messages.push(JSON.parse(line)); } catch (e) { /* a killed run's torn last line */ }
    });
    return messages;
  }

  // The file is served gzip-encoded, which the browser undoes; a plain .gz body is undone here.
  SEAR.fetchReplay = function (url) {
    return fetch(url).then(function (r) {
      if (!r.ok) throw new Error("GET " + url + ": " + r.status);
      return r.arrayBuffer();
    }).then(function (buf) {
      var bytes = new Uint8Array(buf);
      if (bytes.length > 1 && bytes[0] === 0x1f && bytes[1] === 0x8b && window.DecompressionStream) {
        var stream = new Blob([buf]).stream().pipeThrough(new DecompressionStream("gzip"));
        return new Response(stream).text();
      }
      return new TextDecoder().decode(bytes);
    }).then(parse);
  };

  SEAR.Replay = function (view, messages, timeline) {
    this.view = view;
    this.scenes = [];
    this.frames = [];   // {pt: timeline time, scene: index, msg}
    var offset = 0, last = 0, self = this;
    messages.forEach(function (m) {
      if (m.type === "scene") {
        if (self.frames.length) offset = last;
        self.scenes.push({ msg: m, first: self.frames.length });
      } else if (m.type === "frame" && self.scenes.length) {
        last = offset + m.t;
        self.frames.push({ pt: last, scene: self.scenes.length - 1, msg: m });
      }
    });
    this.end = this.frames.length ? this.frames[this.frames.length - 1].pt : 0;
    this.timeline = timeline;
    timeline.min = 0;
    timeline.max = String(this.end);
    timeline.step = "any";
    timeline.value = "0";
    this.shown = -1;        // index of the frame on screen
    this.shownScene = -1;
    this.time = 0;
    this.playing = false;
    this.speed = 1;
    timeline.addEventListener("input", function () { self.playing = false; self.seek(parseFloat(timeline.value)); });
  };

  // The last frame at or before timeline time `pt`.
  SEAR.Replay.prototype.indexAt = function (pt) {
    var lo = 0, hi = this.frames.length - 1, best = 0;
    while (lo <= hi) {
      var mid = (lo + hi) >> 1;
      if (this.frames[mid].pt <= pt + 1e-9) { best = mid; lo = mid + 1; } else hi = mid - 1;
    }
    return best;
  };

  SEAR.Replay.prototype.seek = function (pt) {
    if (!this.frames.length) return;
    this.time = Math.max(0, Math.min(this.end, pt));
    var i = this.indexAt(this.time), f = this.frames[i], view = this.view;
    if (f.scene === this.shownScene && i >= this.shown) {
      for (var k = this.shown + 1; k <= i; k++) view.takeFrame(this.frames[k].msg, true, true);
    } else {
      // Going back, or into another segment: rebuild from the segment's scene. Tracks need every
      // fix; the panels only the frames that can still show in their bounded logs.
      view.takeScene(this.scenes[f.scene].msg);
      var first = this.scenes[f.scene].first, from = i, entries = 0;
      var budget = 2 * SEAR.Panels.MAX_LINES * Math.max(1, Object.keys(view.panels.panels).length);
      while (from > first && entries < budget) {
        (this.frames[from].msg.mcus || []).forEach(function (m) { entries += (m.log || []).length; });
        from--;
      }
      for (var j = first; j <= i; j++) view.takeFrame(this.frames[j].msg, true, j >= from);
      this.shownScene = f.scene;
    }
    this.shown = i;
    this.timeline.value = String(this.time);
    this.report();
  };

  SEAR.Replay.prototype.report = function () {
    var atEnd = this.time >= this.end;
    this.view.setState(atEnd && !this.playing ? "ended" : (this.playing ? "running" : "paused"),
                       "replay " + (this.playing ? "playing" : (atEnd ? "at end" : "paused")) +
                       " · " + (this.speed ? this.speed + "x" : "max"));
  };

  SEAR.Replay.prototype.tick = function (dt) {
    if (!this.playing) return;
    var next = this.time + dt * (this.speed || MAX_SPEED);
    if (next >= this.end) { next = this.end; this.playing = false; }
    this.seek(next);
  };

  SEAR.Replay.prototype.command = function (cmd) {
    if (cmd.cmd === "pause") this.playing = false;
    else if (cmd.cmd === "resume" || cmd.cmd === "start") {
      if (this.time >= this.end) this.seek(0);
      this.playing = true;
    } else if (cmd.cmd === "step") {
      this.playing = false;
      var n = Math.min(this.frames.length - 1, this.shown + 1);
      if (n >= 0) this.seek(this.frames[n].pt);
    } else if (cmd.cmd === "reset") { this.playing = false; this.seek(0); }
    else if (cmd.cmd === "speed") this.speed = cmd.factor;
    this.report();
  };
})();
