// The viewer page: connects to /ws, draws scene and frames (live) or plays /replay, and sends the
// controls and keys back. tools/view/PROTOCOL.md has the messages.
"use strict";
var SEAR = window.SEAR || (window.SEAR = {});

(function () {
  var params = new URLSearchParams(location.search);
  // ?camera=top: fixed, looking down on the whole world; ?camera=free: orbit, following nothing.
  var cameraMode = params.get("camera") || "follow";
  var body = document.body;
  var $ = function (id) { return document.getElementById(id); };

  // ---- three.js set-up
  var holder = $("view");
  var renderer = new THREE.WebGLRenderer({ antialias: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  holder.appendChild(renderer.domElement);
  var scene3 = new THREE.Scene();
  scene3.background = new THREE.Color(0xbfd8ef);
  scene3.add(new THREE.HemisphereLight(0xffffff, 0x445533, 0.75));
  var sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(-30, -20, 60);
  scene3.add(sun);
  var worldRoot = new THREE.Group(), physicsRoot = new THREE.Group(), sensorRoot = new THREE.Group();
  physicsRoot.visible = false;
  scene3.add(worldRoot); scene3.add(physicsRoot); scene3.add(sensorRoot);
  var camera = new THREE.PerspectiveCamera(50, 1, 0.02, 5000);
  camera.up.set(0, 0, 1);
  camera.position.set(-4, -4, 3);
  var controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.enableKeys = false;  // the keys drive robots

  function resize() {
    var w = holder.clientWidth || 1, h = holder.clientHeight || 1;
    renderer.setSize(w, h, true);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    if (cameraMode === "top" && view.topBounds) aimTop(view.topBounds);
  }
  window.addEventListener("resize", function () { resize(); });

  // ---- what is shown
  var view = {
    hello: null, scene: null, robots: {}, sensors: {}, frames: 0, lastFrame: null,
    panels: new SEAR.Panels($("panels")), panelsDirty: false, topBounds: null, replay: null,

    takeScene: function (msg) {
      if (msg !== this.scene) {
        this.scene = msg;
        this.built = SEAR.buildWorld(worldRoot, physicsRoot, msg);
        this.robots = this.built.robots;
        this.sensors = SEAR.buildSensors(sensorRoot, msg);
        this.panels.build(msg);
        fillRobotChoices(msg);
        this.topBounds = null;
        this.aimed = false;
      } else {
        SEAR.clearTracks(this.sensors);
        this.panels.clear();
      }
    },

    // tracks: add GPS points; panels: feed the MCU panels (scrubbing skips the oldest frames).
    takeFrame: function (msg, tracks, panels) {
      if (!this.scene) return;
      SEAR.poseWorld(this.built, msg);
      SEAR.updateSensors(this.sensors, this.robots, msg, tracks);
      if (panels) this.panels.takeFrame(msg);
      this.panelsDirty = true;
      this.lastFrame = msg;
      this.frames++;
      body.dataset.frames = String(this.frames);
      body.dataset.simTime = String(msg.t);
      $("time").textContent = "t = " + msg.t.toFixed(3) + " s";
      if (!this.aimed) { aimCamera(msg); this.aimed = true; }
    },

    setState: function (state, text) {
      body.dataset.state = state;
      $("status").textContent = text;
      $("status").className = state;
    }
  };
  SEAR.view = view;

  // ---- camera
  function aimTop(bounds) {
    var c = bounds.getCenter(new THREE.Vector2()), s = bounds.getSize(new THREE.Vector2());
    var half = Math.PI * camera.fov / 360;
    var h = Math.max(s.y / 2, s.x / 2 / camera.aspect) / Math.tan(half) * 1.05;
    camera.up.set(0, 1, 0);  // north up on the screen
    camera.position.set(c.x, c.y, h);
    camera.lookAt(c.x, c.y, 0);
    camera.updateProjectionMatrix();
  }

  function aimCamera(frame) {
    if (cameraMode === "top") {
      var b = SEAR.worldBounds(view.scene);
      (frame.robots || []).forEach(function (r) { b.expandByPoint(new THREE.Vector2(r.pos[0], r.pos[1])); });
      if (b.isEmpty()) b.set(new THREE.Vector2(-5, -5), new THREE.Vector2(5, 5));
      b.expandByScalar(1);
      var s = b.getSize(new THREE.Vector2()), c = b.getCenter(new THREE.Vector2());
      var span = Math.max(4, s.x, s.y);  // a lone robot still shows at a useful size
      b.set(new THREE.Vector2(c.x - span / 2, c.y - span / 2), new THREE.Vector2(c.x + span / 2, c.y + span / 2));
      view.topBounds = b;
      controls.enabled = false;
      aimTop(b);
      return;
    }
    var r = followed();
    if (r) {
      // Behind the robot and above it, looking along its heading.
      var p = r.group.position;
      var ahead = new THREE.Vector3(1, 0, 0).applyQuaternion(r.group.quaternion).setZ(0).normalize();
      controls.target.copy(p);
      camera.position.set(p.x - 1.8 * ahead.x, p.y - 1.8 * ahead.y, p.z + 1.2);
    }
    controls.update();
  }

  function followed() {
    var v = $("camera").value;
    return v.indexOf("follow:") === 0 ? view.robots[v.slice(7)] : null;
  }

  // Following moves the camera with the robot, so the user can still orbit around it.
  var lastTarget = new THREE.Vector3();
  function followStep() {
    if (cameraMode === "top") return;
    var r = followed();
    if (r) {
      lastTarget.copy(r.group.position).sub(controls.target);
      camera.position.add(lastTarget);
      controls.target.copy(r.group.position);
    }
    controls.update();
  }

  function fillRobotChoices(scene) {
    var cam = $("camera"), keys = $("keyrobot"), keep = cam.value;
    cam.textContent = ""; keys.textContent = "";
    (scene.robots || []).forEach(function (r) {
      var o = document.createElement("option");
      o.value = "follow:" + r.name; o.textContent = "follow " + r.name;
      cam.appendChild(o);
      if (r.keyboard) {
        var k = document.createElement("option");
        k.value = r.name; k.textContent = r.name;
        keys.appendChild(k);
      }
    });
    var free = document.createElement("option");
    free.value = "free"; free.textContent = "free camera";
    cam.appendChild(free);
    if (keep && Array.prototype.some.call(cam.options, function (o) { return o.value === keep; })) cam.value = keep;
    else if (cameraMode === "free") cam.value = "free";
    $("keys").hidden = keys.options.length === 0;
    cam.disabled = cameraMode === "top";
  }

  // ---- talking to the server
  var socket = null;
  function send(cmd) {
    if (view.replay) { view.replay.command(cmd); return; }
    if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(cmd));
  }

  function onStatus(m) {
    // Held at t = 0 for Start is not a pause the user made: say what to do.
    view.waiting = !!m.waiting;
    var state = m.ended ? "ended" : (m.waiting ? "waiting" : (m.paused ? "paused" : "running"));
    var speed = m.speed ? m.speed + "x" : "max";
    var text = (m.waiting ? "waiting at t = 0: " + (m.reason || "press Space or Start") : state) +
               (m.ended && m.reason ? ": " + m.reason : "") + " · speed " + speed +
               " · RTF " + (typeof m.rtf === "number" ? m.rtf.toFixed(2) : "-") +
               (m.frames_skipped ? " · " + m.frames_skipped + " frames skipped (slow link)" : "");
    view.setState(state, text);
    var sel = $("speed");
    if (document.activeElement !== sel) {
      // A speed the list does not offer (--realtime 0.5) is added, so the box never shows blank.
      var value = String(m.speed);
      if (![].some.call(sel.options, function (o) { return o.value === value; })) {
        var option = document.createElement("option");
        option.value = value;
        option.textContent = m.speed ? m.speed + "x" : "max";
        sel.appendChild(option);
      }
      sel.value = value;
    }
  }

  function onMessage(m) {
    if (m.type === "hello") {
      view.hello = m;
      body.dataset.mode = m.mode;
      document.title = "SEAR · " + m.project + (m.mode === "replay" ? " (replay)" : "");
      $("project").textContent = m.project;
      if (m.mode === "replay") startReplay();
    } else if (m.type === "scene") {
      if (!view.replay) view.takeScene(m);
    } else if (m.type === "frame") {
      if (!view.replay) view.takeFrame(m, true, true);
    } else if (m.type === "status") {
      if (!view.replay) onStatus(m);
    }
  }

  function connect() {
    socket = new WebSocket((location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/ws");
    socket.onmessage = function (ev) {
      var m;
      try { m = JSON.parse(ev.data); } catch (e) { return; }
      onMessage(m);
    };
    socket.onclose = function (ev) {
      if (view.replay) return;
      // The server says why it closed a page (too many pages watching, say).
      $("status").textContent += " · disconnected" + (ev.reason ? ": " + ev.reason : "");
      body.dataset.connected = "false";
    };
    socket.onopen = function () { body.dataset.connected = "true"; };
  }

  function startReplay() {
    body.classList.add("replay");
    view.setState("paused", "loading the replay…");
    SEAR.fetchReplay("/replay").then(function (messages) {
      view.replay = new SEAR.Replay(view, messages, $("timeline"));
      view.replay.speed = parseFloat($("speed").value);
      view.replay.seek(0);
    }).catch(function (e) {
      view.setState("ended", "replay: " + e.message);
    });
  }

  // ---- controls
  function button(id, make) {
    $(id).addEventListener("click", function () { send(make()); $(id).blur(); });
  }
  button("pause", function () { return { cmd: "pause" }; });
  button("resume", function () { return { cmd: "resume" }; });
  button("step", function () { return { cmd: "step", n: Math.max(1, parseInt($("stepn").value, 10) || 1) }; });
  button("reset", function () { return { cmd: "reset" }; });
  button("start", function () { return { cmd: "start" }; });
  $("speed").addEventListener("change", function () {
    send({ cmd: "speed", factor: parseFloat($("speed").value) });
    $("speed").blur();
  });
  $("keyrobot").addEventListener("change", function () { $("keyrobot").blur(); });
  $("physics").addEventListener("change", function () { physicsRoot.visible = $("physics").checked; });
  $("camera").addEventListener("change", function () {
    var r = followed();
    if (r) { controls.target.copy(r.group.position); controls.update(); }
    $("camera").blur();
  });

  // The original SEAR's keys, and the arrows; Space starts the firmware.
  var KEYS = { h: "h", k: "k", u: "u", j: "j", ArrowUp: "ArrowUp", ArrowDown: "ArrowDown",
               ArrowLeft: "ArrowLeft", ArrowRight: "ArrowRight", Enter: "Enter" };
  function typing(target) {
    var tag = target && target.tagName;
    return tag === "INPUT" && target.type !== "checkbox" && target.type !== "range" || tag === "TEXTAREA";
  }
  function onKey(ev, down) {
    if (typing(ev.target) || ev.ctrlKey || ev.altKey || ev.metaKey) return;
    if (ev.key === " ") {
      ev.preventDefault();
      if (down && !ev.repeat) send({ cmd: "start" });
      return;
    }
    var key = KEYS[ev.key.length === 1 ? ev.key.toLowerCase() : ev.key];
    if (!key) return;
    ev.preventDefault();
    // A held U or arrow repeats, and each repeat adds throttle (the original SEAR's feel); a held
    // Enter must not reset over and over.
    if (view.replay || (ev.repeat && key === "Enter")) return;
    // Enter resets the run, whoever drives: a project whose robots all have MCUs has no key robot.
    if (key === "Enter") {
      if (down) send({ cmd: "reset" });
      return;
    }
    var robot = $("keyrobot").value;
    if (robot) send({ cmd: "key", key: key, down: down, robot: robot });
  }
  document.addEventListener("keydown", function (ev) { onKey(ev, true); });
  document.addEventListener("keyup", function (ev) { onKey(ev, false); });

  // ---- drawing
  var lastWall = performance.now(), lastPanels = 0;
  function draw(now) {
    var dt = Math.min(0.25, (now - lastWall) / 1000);
    lastWall = now;
    if (view.replay) view.replay.tick(dt);
    followStep();
    renderer.render(scene3, camera);
    if (view.panelsDirty && now - lastPanels > 150) {
      view.panels.render();
      view.panelsDirty = false;
      lastPanels = now;
    }
    requestAnimationFrame(draw);
  }

  body.dataset.frames = "0";
  body.dataset.state = "connecting";
  resize();
  connect();
  requestAnimationFrame(draw);
})();
