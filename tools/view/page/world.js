// The world in three.js from a "scene" message (tools/view/PROTOCOL.md): terrain, obstacles, robots
// with their wheels, and the physics shapes as wireframes. World frame ENU, z up, as in SEAR.
"use strict";
var SEAR = window.SEAR || (window.SEAR = {});

(function () {
  // Each robot gets its own colour; the first is a saturated red-orange that nothing else in the
  // scene uses, so the browser tests can find the robot's pixels by colour.
  SEAR.ROBOT_COLOURS = [0xff2a00, 0x2060ff, 0xffd000, 0xb000ff, 0x00d0d0, 0xff00a0];
  var OBSTACLE_COLOUR = 0x8c8c8c;
  var WIRE_COLOUR = 0x00ff40;

  function quat(q) {
    return q ? new THREE.Quaternion(q[1], q[2], q[3], q[0]) : new THREE.Quaternion();
  }
  SEAR.quat = quat;

  function vec(p) {
    return p ? new THREE.Vector3(p[0], p[1], p[2] || 0) : new THREE.Vector3();
  }
  SEAR.vec = vec;

  // A shape of the protocol ("box" | "cylinder" | "sphere" | "mesh") as a geometry in its own
  // frame. ODE cylinders run along z, three.js ones along y: turn them.
  function shapeGeometry(s) {
    if (s.shape === "box") {
      var z = s.size || [1, 1, 1];
      return new THREE.BoxBufferGeometry(z[0], z[1], z[2]);
    }
    if (s.shape === "cylinder") {
      var g = new THREE.CylinderBufferGeometry(s.radius, s.radius, s.length, 24);
      g.rotateX(Math.PI / 2);
      return g;
    }
    if (s.shape === "sphere") return new THREE.SphereBufferGeometry(s.radius, 24, 16);
    if (s.shape === "mesh" && s.vertices && s.indices) {
      var m = new THREE.BufferGeometry();
      m.setAttribute("position", new THREE.Float32BufferAttribute(s.vertices, 3));
      m.setIndex(s.indices);
      m.computeVertexNormals();
      return m;
    }
    return null;
  }
  SEAR.shapeGeometry = shapeGeometry;

  // Green in the lows to brown and white on the tops.
  function heightColour(f, out) {
    var stops = [[0.20, 0.45, 0.18], [0.45, 0.55, 0.25], [0.55, 0.45, 0.30], [0.90, 0.90, 0.88]];
    var x = Math.max(0, Math.min(1, f)) * (stops.length - 1);
    var i = Math.min(stops.length - 2, Math.floor(x));
    var u = x - i;
    out.setRGB(stops[i][0] + (stops[i + 1][0] - stops[i][0]) * u,
               stops[i][1] + (stops[i + 1][1] - stops[i][1]) * u,
               stops[i][2] + (stops[i + 1][2] - stops[i][2]) * u);
  }

  function colourByHeight(geometry) {
    var pos = geometry.getAttribute("position");
    var lo = Infinity, hi = -Infinity, i;
    for (i = 0; i < pos.count; i++) { lo = Math.min(lo, pos.getZ(i)); hi = Math.max(hi, pos.getZ(i)); }
    var colours = new Float32Array(pos.count * 3), c = new THREE.Color();
    for (i = 0; i < pos.count; i++) {
      heightColour(hi > lo ? (pos.getZ(i) - lo) / (hi - lo) : 0, c);
      colours[3 * i] = c.r; colours[3 * i + 1] = c.g; colours[3 * i + 2] = c.b;
    }
    geometry.setAttribute("color", new THREE.BufferAttribute(colours, 3));
  }

  // Heightmap: row 0 is the north edge, the grid spans size_m centred on the origin.
  function heightmapGeometry(t) {
    var nx = t.grid[0], ny = t.grid[1], sx = t.size_m[0], sy = t.size_m[1];
    var positions = new Float32Array(nx * ny * 3), indices = [], r, c;
    for (r = 0; r < ny; r++) {
      for (c = 0; c < nx; c++) {
        var k = 3 * (r * nx + c);
        positions[k] = -sx / 2 + sx * c / (nx - 1);
        positions[k + 1] = sy / 2 - sy * r / (ny - 1);
        positions[k + 2] = t.heights_m[r][c];
      }
    }
    for (r = 0; r + 1 < ny; r++) {
      for (c = 0; c + 1 < nx; c++) {
        var a = r * nx + c, b = a + 1, d = a + nx, e = d + 1;
        indices.push(a, d, b, b, d, e);  // counter-clockwise seen from above
      }
    }
    var g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.BufferAttribute(positions, 3));
    g.setIndex(indices);
    g.computeVertexNormals();
    return g;
  }

  function terrainObject(t) {
    var g;
    if (t.kind === "mesh" && t.vertices && t.indices) {
      g = shapeGeometry({ shape: "mesh", vertices: t.vertices, indices: t.indices });
    } else if (t.kind === "heightmap" && t.grid && t.heights_m) {
      g = heightmapGeometry(t);
    } else {
      var size = (t.size_m && t.size_m[0] > 0) ? t.size_m : [200, 200];
      g = new THREE.PlaneBufferGeometry(size[0], size[1], 1, 1);
      var plane = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ color: 0x5f8a4a }));
      var grid = new THREE.GridHelper(Math.max(size[0], size[1]), Math.round(Math.max(size[0], size[1])), 0x2f4a24, 0x3f6232);
      grid.rotation.x = Math.PI / 2;  // GridHelper lies in x-z
      grid.position.z = 0.001;
      var group = new THREE.Group();
      group.add(plane); group.add(grid);
      return group;
    }
    colourByHeight(g);
    return new THREE.Mesh(g, new THREE.MeshLambertMaterial({ vertexColors: THREE.VertexColors, side: THREE.DoubleSide }));
  }

  function wireframe(geometry) {
    return new THREE.LineSegments(new THREE.WireframeGeometry(geometry),
                                  new THREE.LineBasicMaterial({ color: WIRE_COLOUR }));
  }

  function place(object, s) {
    object.position.copy(vec(s.pos));
    object.quaternion.copy(quat(s.quat));
    return object;
  }

  // Builds everything a scene message describes under `root` (emptied first). Returns the robots
  // by name ({group, wires, wheels[], colour, desc}) and the obstacles by name ({mesh, wire}).
  SEAR.buildWorld = function (root, physicsRoot, scene) {
    while (root.children.length) root.remove(root.children[0]);
    while (physicsRoot.children.length) physicsRoot.remove(physicsRoot.children[0]);
    var world = scene.world || {};
    if (world.terrain) root.add(terrainObject(world.terrain));
    var obstacles = {};
    (world.obstacles || []).forEach(function (o) {
      var g = shapeGeometry(o);
      if (!g) return;
      var mat = new THREE.MeshLambertMaterial({ color: OBSTACLE_COLOUR });
      var mesh = place(new THREE.Mesh(g, mat), o), wire = place(wireframe(g), o);
      root.add(mesh);
      physicsRoot.add(wire);
      obstacles[o.name] = { mesh: mesh, wire: wire };
    });
    var robots = {};
    (scene.robots || []).forEach(function (r, i) {
      var colour = SEAR.ROBOT_COLOURS[i % SEAR.ROBOT_COLOURS.length];
      var group = new THREE.Group();
      var size = (r.body && r.body.size) || [0.3, 0.2, 0.08];
      // A URDF robot brings its own visuals, each on its body (-1: the chassis, else a wheel).
      var visuals = r.visuals || [];
      function visualMesh(v) {
        var g = shapeGeometry(v);
        if (!g) return null;
        var c = v.rgba || [0.7, 0.7, 0.7, 1];
        return place(new THREE.Mesh(g, new THREE.MeshLambertMaterial({
          color: new THREE.Color(c[0], c[1], c[2]), transparent: c[3] < 1, opacity: c[3] })), v);
      }
      if (visuals.length) {
        visuals.forEach(function (v) {
          var m = v.body === -1 && v.joint === undefined ? visualMesh(v) : null;
          if (m) group.add(m);
        });
      } else {
        // Unlit, so the robot keeps one colour whatever the light (the tests look for it).
        group.add(new THREE.Mesh(new THREE.BoxBufferGeometry(size[0], size[1], size[2]),
                                 new THREE.MeshBasicMaterial({ color: colour })));
        // A dark nose shows which way is forward.
        var nose = new THREE.Mesh(new THREE.BoxBufferGeometry(size[0] * 0.15, size[1] * 0.6, size[2] * 0.3),
                                  new THREE.MeshBasicMaterial({ color: 0x202020 }));
        nose.position.set(size[0] * 0.45, 0, size[2] * 0.55);
        group.add(nose);
      }
      // The physics shapes (chassis, wheels, treads, casters) as the scene gives them, in the
      // robot's frame: they ride with the chassis.
      var wires = new THREE.Group();
      (r.geoms || []).forEach(function (s) {
        var g = shapeGeometry(s);
        if (g) wires.add(place(wireframe(g), s));
      });
      physicsRoot.add(wires);
      var wheels = (r.wheels || []).map(function (w, index) {
        var own = visuals.filter(function (v) { return v.body === index; });
        if (own.length) {
          var body = new THREE.Group();
          own.forEach(function (v) { var m = visualMesh(v); if (m) body.add(m); });
          root.add(body);
          return { mesh: body };
        }
        var g = new THREE.CylinderBufferGeometry(w.radius, w.radius, w.width, 20);
        g.rotateX(Math.PI / 2);  // the wheel body's axle is its z, as ODE's cylinder
        var m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ color: 0x1a1a1a }));
        // A light spoke so the spin shows.
        var spoke = new THREE.Mesh(new THREE.BoxBufferGeometry(w.radius * 1.6, w.radius * 0.25, w.width * 1.05),
                                   new THREE.MeshLambertMaterial({ color: 0x9a9a9a }));
        m.add(spoke);
        root.add(m);
        return { mesh: m };
      });
      // A URDF's live links: their visuals and physics shapes, each on its own body, posed by the frames.
      var joints = (r.joints || []).map(function (j, index) {
        var body = new THREE.Group(), wire = new THREE.Group();
        visuals.forEach(function (v) {
          if (v.joint !== index) return;
          var m = visualMesh(v);
          if (m) body.add(m);
        });
        (j.geoms || []).forEach(function (s) {
          var g = shapeGeometry(s);
          if (g) wire.add(place(wireframe(g), s));
        });
        root.add(body);
        physicsRoot.add(wire);
        return { mesh: body, wire: wire };
      });
      root.add(group);
      robots[r.name] = { group: group, wires: wires, wheels: wheels, joints: joints, colour: colour, desc: r };
    });
    return { robots: robots, obstacles: obstacles };
  };

  // Moves the robots, and the obstacles that can be pushed, to a frame's poses.
  SEAR.poseWorld = function (built, frame) {
    (frame.obstacles || []).forEach(function (fo) {
      var o = built.obstacles[fo.name];
      if (!o) return;
      o.mesh.position.copy(vec(fo.pos));
      o.mesh.quaternion.copy(quat(fo.quat));
      o.wire.position.copy(o.mesh.position);
      o.wire.quaternion.copy(o.mesh.quaternion);
    });
    var robots = built.robots;
    (frame.robots || []).forEach(function (fr) {
      var r = robots[fr.name];
      if (!r) return;
      r.group.position.copy(vec(fr.pos));
      r.group.quaternion.copy(quat(fr.quat));
      r.wires.position.copy(r.group.position);
      r.wires.quaternion.copy(r.group.quaternion);
      (fr.wheels || []).forEach(function (w, i) {
        var mine = r.wheels[i];
        if (!mine) return;
        mine.mesh.position.copy(vec(w.pos));
        mine.mesh.quaternion.copy(quat(w.quat));
      });
      (fr.joints || []).forEach(function (j, i) {
        var mine = r.joints[i];
        if (!mine) return;
        mine.mesh.position.copy(vec(j.pos));
        mine.mesh.quaternion.copy(quat(j.quat));
        mine.wire.position.copy(mine.mesh.position);
        mine.wire.quaternion.copy(mine.mesh.quaternion);
      });
    });
  };

  // The world's extent for the top-down camera: a heightmap's or mesh's size, or (on a plane,
  // which may be vast) what stands on it.
  SEAR.worldBounds = function (scene) {
    var world = scene.world || {}, t = world.terrain || {};
    var box = new THREE.Box2();
    if (t.kind !== "plane" && t.size_m && t.size_m[0] > 0) {
      box.expandByPoint(new THREE.Vector2(-t.size_m[0] / 2, -t.size_m[1] / 2));
      box.expandByPoint(new THREE.Vector2(t.size_m[0] / 2, t.size_m[1] / 2));
      return box;
    }
    (world.obstacles || []).forEach(function (o) {
      var reach = o.size ? Math.hypot(o.size[0], o.size[1]) / 2 : (o.radius || 0.5);
      box.expandByPoint(new THREE.Vector2(o.pos[0] - reach, o.pos[1] - reach));
      box.expandByPoint(new THREE.Vector2(o.pos[0] + reach, o.pos[1] + reach));
    });
    return box;
  };
})();
