// What the sensors see, drawn from frames: IR and sonar cones with their hit points, LIDAR points
// from a fan's ranges, the GPS fixes against the true track, and each robot's path.
"use strict";
var SEAR = window.SEAR || (window.SEAR = {});

(function () {
  var CONE_COLOUR = 0xffee55, HIT_COLOUR = 0xff00ff, LIDAR_COLOUR = 0x00e5ff;
  var FIX_COLOUR = 0x0040ff, TRUTH_COLOUR = 0xffffff, PATH_COLOUR = 0xff8c1a;
  var PATH_STEP_M = 0.02;  // a point of a robot's path each 2 cm it moves: smooth at any zoom the page has
  var TRACK_POINTS = 20000;  // per line: a long run's track stays drawable

  function track(colour) {
    var g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.BufferAttribute(new Float32Array(TRACK_POINTS * 3), 3));
    g.setDrawRange(0, 0);
    var line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: colour }));
    line.frustumCulled = false;
    line.count = 0;
    return line;
  }

  function pushPoint(line, p) {
    var attr = line.geometry.getAttribute("position");
    if (line.count >= TRACK_POINTS) {  // drop the oldest half rather than stop drawing
      attr.array.copyWithin(0, (TRACK_POINTS / 2) * 3);
      line.count = TRACK_POINTS / 2;
    }
    attr.setXYZ(line.count, p[0], p[1], (p[2] || 0) + 0.02);
    line.count++;
    attr.needsUpdate = true;
    line.geometry.setDrawRange(0, line.count);
  }

  // One visual per sensor of the scene. Cones and fans hang off a mount that follows the robot.
  SEAR.buildSensors = function (root, scene) {
    while (root.children.length) root.remove(root.children[0]);
    var byRobot = {};
    (scene.robots || []).forEach(function (r) {
      var list = {};
      (r.sensors || []).forEach(function (s) {
        var v = { desc: s, kind: s.view };
        if (s.view === "cone") {
          var half = Math.max(0.5, (s.beam_deg || 5) / 2) * Math.PI / 180;
          var g = new THREE.ConeBufferGeometry(Math.tan(half), 1, 20, 1, true);
          g.rotateZ(Math.PI / 2);       // apex to -x
          g.translate(0.5, 0, 0);       // apex at the mount, opening along +x
          v.mount = new THREE.Group();
          v.cone = new THREE.Mesh(g, new THREE.MeshBasicMaterial({
            color: CONE_COLOUR, transparent: true, opacity: 0.25, depthWrite: false, side: THREE.DoubleSide }));
          v.mount.add(v.cone);
          v.hit = new THREE.Mesh(new THREE.SphereBufferGeometry(0.025, 10, 8),
                                 new THREE.MeshBasicMaterial({ color: HIT_COLOUR }));
          v.hit.visible = false;
          v.mount.add(v.hit);
          root.add(v.mount);
        } else if (s.view === "fan") {
          v.mount = new THREE.Group();
          var pg = new THREE.BufferGeometry();
          pg.setAttribute("position", new THREE.BufferAttribute(new Float32Array(Math.max(s.count || 0, 721) * 3), 3));
          pg.setDrawRange(0, 0);
          v.points = new THREE.Points(pg, new THREE.PointsMaterial({ color: LIDAR_COLOUR, size: 4, sizeAttenuation: false }));
          v.points.frustumCulled = false;
          v.mount.add(v.points);
          root.add(v.mount);
        } else if (s.view === "gps") {
          v.fixes = track(FIX_COLOUR);
          v.truth = track(TRUTH_COLOUR);
          root.add(v.fixes); root.add(v.truth);
        }
        list[s.name] = v;
      });
      // The robot's own path, under the name no sensor can have (names are XML attributes).
      var path = { kind: "path", line: track(PATH_COLOUR) };
      root.add(path.line);
      list[" path"] = path;
      byRobot[r.name] = list;
    });
    return byRobot;
  };

  var mountMatrix = new THREE.Matrix4(), robotMatrix = new THREE.Matrix4();

  function placeMount(v, robotGroup) {
    var s = v.desc;
    mountMatrix.compose(SEAR.vec(s.pos), SEAR.quat(s.quat), new THREE.Vector3(1, 1, 1));
    robotMatrix.compose(robotGroup.position, robotGroup.quaternion, new THREE.Vector3(1, 1, 1));
    robotMatrix.multiply(mountMatrix);
    robotMatrix.decompose(v.mount.position, v.mount.quaternion, v.mount.scale);
  }

  // Draws one frame's readings. `tracks` false: only the poses (scrubbing redraws tracks itself).
  SEAR.updateSensors = function (sensors, robots, frame, tracks) {
    // Devices whose model has been fed a sample: until then a cone's range is no reading at all,
    // and drawn at full length it would cross walls at t = 0.
    var fed = {};
    (frame.mcus || []).forEach(function (m) {
      Object.keys(m.truth || {}).forEach(function (d) { fed[m.id + "/" + d] = true; });
    });
    (frame.robots || []).forEach(function (fr) {
      var list = sensors[fr.name], robot = robots[fr.name];
      if (!list || !robot) return;
      var path = list[" path"];
      if (tracks && path && fr.pos) {
        var attr = path.line.geometry.getAttribute("position"), n = path.line.count;
        if (!n || Math.hypot(fr.pos[0] - attr.getX(n - 1), fr.pos[1] - attr.getY(n - 1)) >= PATH_STEP_M)
          pushPoint(path.line, [fr.pos[0], fr.pos[1], fr.pos[2] - 0.01]);
      }
      (fr.sensors || []).forEach(function (f) {
        var v = list[f.name];
        if (!v) return;
        if (v.kind === "cone") {
          placeMount(v, robot.group);
          var max = v.desc.max_m || 1;
          var known = f.range_m !== null && f.range_m !== undefined;
          v.cone.visible = known || !!fed[v.desc.mcu + "/" + f.name];
          var len = known ? f.range_m : max;
          v.cone.scale.set(Math.max(len, 1e-3), Math.max(len, 1e-3), Math.max(len, 1e-3));
          v.hit.visible = f.range_m !== null && f.range_m !== undefined;
          v.hit.position.set(len, 0, 0);
        } else if (v.kind === "fan" && f.ranges_m) {
          placeMount(v, robot.group);
          var attr = v.points.geometry.getAttribute("position"), n = 0;
          // The scan says its own angles (a mode change alters them); the scene's are the default.
          var start = (f.start_deg !== undefined ? f.start_deg : (v.desc.start_deg || 0)) * Math.PI / 180;
          var step = (f.step_deg !== undefined ? f.step_deg : (v.desc.step_deg || 1)) * Math.PI / 180;
          for (var i = 0; i < f.ranges_m.length && n < attr.count; i++) {
            var r = f.ranges_m[i];
            if (r === null || r === undefined) continue;
            var a = start + i * step;
            attr.setXYZ(n++, r * Math.cos(a), r * Math.sin(a), 0);
          }
          attr.needsUpdate = true;
          v.points.geometry.setDrawRange(0, n);
        } else if (v.kind === "gps" && tracks) {
          if (f.fix) pushPoint(v.fixes, f.fix);
          if (f.truth) pushPoint(v.truth, f.truth);
        }
      });
    });
  };

  SEAR.clearTracks = function (sensors) {
    Object.keys(sensors).forEach(function (robot) {
      Object.keys(sensors[robot]).forEach(function (name) {
        var v = sensors[robot][name];
        if (v.kind !== "gps" && v.kind !== "path") return;
        (v.kind === "path" ? [v.line] : [v.fixes, v.truth]).forEach(function (line) { line.count = 0; line.geometry.setDrawRange(0, 0); });
      });
    });
  };
})();
