// The 3D viewer of viewer.html (dbtools/site/meshes.py writes its data): the panels of one case side by side on
// one canvas (a viewport each, one camera and OrbitControls shared), three.js r111 (BufferGeometry.setAttribute).
// Data arrive as scripts (file:// has no fetch): meshes/index.js sets DB_CASES, meshes/CASE.js calls DB_MESHES.add.
// window.DB_VIEWER_DRAWN counts the frames drawn (the browser test waits for it).
"use strict";
var DB_MESHES = {
  cases: {},
  waiting: null,
  add: function (rec) {
    this.cases[rec.name] = rec;
    // only the case last asked for is shown (a reader may pick another before the first has loaded)
    if (this.waiting && this.waiting.name === rec.name) { var f = this.waiting.done; this.waiting = null; f(rec); }
  }
};
window.DB_VIEWER_DRAWN = 0;

(function () {
  var ROLE_COLOURS = [[0.62, 0.66, 0.72], [0.86, 0.32, 0.30], [0.97, 0.85, 0.25]];  // fixed, free, handle
  // viridis, sampled at 0, 0.25, 0.5, 0.75, 1
  var RAMP = [[0.267, 0.005, 0.329], [0.229, 0.322, 0.546], [0.128, 0.567, 0.551], [0.369, 0.789, 0.383],
              [0.993, 0.906, 0.144]];
  var canvas = document.getElementById("canvas"), labels = document.getElementById("labels");
  var status = document.getElementById("status");
  var renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setScissorTest(true);
  var camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
  var controls = new THREE.OrbitControls(camera, canvas);
  var panels = [], current = null;

  function decode(b64, Type) {
    var s = atob(b64), bytes = new Uint8Array(s.length);
    for (var i = 0; i < s.length; i++) bytes[i] = s.charCodeAt(i);
    return new Type(bytes.buffer);
  }

  function ramp(t) {
    t = Math.min(Math.max(t, 0), 1) * (RAMP.length - 1);
    var k = Math.min(Math.floor(t), RAMP.length - 2), f = t - k, a = RAMP[k], b = RAMP[k + 1];
    return [a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f];
  }

  function distances(V, R, diag) {
    var n = V.length / 3, d = new Float32Array(n);
    for (var i = 0; i < n; i++) {
      var x = V[3 * i] - R[3 * i], y = V[3 * i + 1] - R[3 * i + 1], z = V[3 * i + 2] - R[3 * i + 2];
      d[i] = Math.sqrt(x * x + y * y + z * z) / diag;
    }
    return d;
  }

  function build(rec) {
    var F = decode(rec.F, Uint32Array), roles = decode(rec.roles, Uint8Array);
    var handle = [];
    for (var i = 0; i < roles.length; i++) if (roles[i] === 2) handle.push(i);
    panels = rec.configs.map(function (c) {
      var V = decode(c.V, Float32Array), g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.BufferAttribute(V, 3));
      g.setAttribute("color", new THREE.BufferAttribute(new Float32Array(V.length), 3));
      g.setIndex(new THREE.BufferAttribute(F, 1));
      g.computeVertexNormals();
      g.computeBoundingBox();
      var scene = new THREE.Scene();
      scene.background = new THREE.Color(0xffffff);
      scene.add(new THREE.Mesh(g, new THREE.MeshLambertMaterial({vertexColors: THREE.VertexColors,
                                                                 side: THREE.DoubleSide})));
      var hp = new Float32Array(handle.length * 3);
      handle.forEach(function (v, k) {
        hp[3 * k] = V[3 * v]; hp[3 * k + 1] = V[3 * v + 1]; hp[3 * k + 2] = V[3 * v + 2];
      });
      var hg = new THREE.BufferGeometry();
      hg.setAttribute("position", new THREE.BufferAttribute(hp, 3));
      scene.add(new THREE.Points(hg, new THREE.PointsMaterial({color: 0xe0218a, size: 3, sizeAttenuation: false})));
      scene.add(new THREE.AmbientLight(0xffffff, 0.45));
      var light = new THREE.DirectionalLight(0xffffff, 0.6);
      scene.add(light);
      return {key: c.key, label: c.label, V: V, geometry: g, scene: scene, light: light};
    });
    var ref = document.getElementById("ref");
    ref.innerHTML = "";
    panels.forEach(function (p) {
      var o = document.createElement("option");
      o.value = p.key; o.textContent = p.label;
      ref.appendChild(o);
    });
    var roleOption = document.createElement("option");
    roleOption.value = "roles"; roleOption.textContent = "none: colour by role (fixed / region of interest / handle)";
    ref.appendChild(roleOption);
    ref.value = panels.some(function (p) { return p.key === "lap"; }) ? "lap" : "rest";
    frame();
    colour(rec, roles);
    layout();
  }

  function refKey() { return document.getElementById("ref").value; }

  function colour(rec, roles) {
    var byRole = refKey() === "roles", ref = panels.filter(function (p) { return p.key === refKey(); })[0];
    var dists = panels.map(function (p) {
      return byRole || p.key === "rest" || p === ref ? null : distances(p.V, ref.V, rec.diag);
    });
    // One scale for all panels, set by the results of about the rest size: a blown-up result (TF's free scale)
    // would leave every other panel at the bottom colour; it saturates instead.
    var hi = 0, hiAll = 0, saturated = [];
    dists.forEach(function (d, k) {
      if (!d) return;
      var m = 0;
      for (var i = 0; i < d.length; i++) m = Math.max(m, d[i]);
      hiAll = Math.max(hiAll, m);
      if (panels[k].scale <= 2) hi = Math.max(hi, m); else saturated.push(panels[k].label);
    });
    if (hi === 0) { hi = hiAll; saturated = []; }
    panels.forEach(function (p, k) {
      var col = p.geometry.attributes.color.array, d = dists[k];
      for (var i = 0; i < roles.length; i++) {
        var c = p.key === "rest" || byRole ? ROLE_COLOURS[roles[i]] || ROLE_COLOURS[1]
              : d ? ramp(hi > 0 ? d[i] / hi : 0) : [0.8, 0.8, 0.8];  // the reference itself: grey
        col[3 * i] = c[0]; col[3 * i + 1] = c[1]; col[3 * i + 2] = c[2];
      }
      p.geometry.attributes.color.needsUpdate = true;
    });
    document.getElementById("cb-lo").textContent = "0";
    document.getElementById("cb-hi").textContent = byRole ? "(colours by role)"
      : hi.toPrecision(3) + " rest bounding-box diagonals from " + ref.label +
        (saturated.length ? " (" + saturated.join(", ") + ": up to " + hiAll.toPrecision(3) + ", saturated)" : "");
  }

  function frame() {
    // The camera on the rest mesh and the results of about its size: a result far larger (TF's scale running
    // away) would shrink every other panel to a few pixels; its label says so, zoom out to see it whole.
    var rest = panels[0].geometry.boundingBox, size = rest.getSize(new THREE.Vector3()).length();
    var box = new THREE.Box3();
    panels.forEach(function (p) {
      p.scale = p.geometry.boundingBox.getSize(new THREE.Vector3()).length() / size;
      if (p.scale <= 2) box.union(p.geometry.boundingBox);
    });
    var c = box.getCenter(new THREE.Vector3()), r = box.getSize(new THREE.Vector3()).length() / 2;
    controls.target.copy(c);
    camera.position.set(c.x, c.y - 3.2 * r, c.z + 0.5 * r);
    camera.up.set(0, 0, 1);
    camera.near = r / 100; camera.far = r * 100;
    camera.updateProjectionMatrix();
    controls.update();
  }

  function layout() {
    var n = Math.max(panels.length, 1), w = canvas.parentNode.clientWidth;
    var cols = Math.min(n, Math.max(1, Math.floor(w / 220))), rows = Math.ceil(n / cols);
    var pw = Math.floor(w / cols), ph = Math.round(pw * 1.2);
    renderer.setSize(pw * cols, ph * rows);
    camera.aspect = pw / ph;
    camera.updateProjectionMatrix();
    labels.innerHTML = "";
    panels.forEach(function (p, k) {
      p.rect = {x: (k % cols) * pw, y: Math.floor(k / cols) * ph, w: pw, h: ph};
      var l = document.createElement("div");
      l.className = "label";
      l.style.left = p.rect.x + "px"; l.style.top = p.rect.y + "px"; l.style.width = pw + "px";
      var t = document.createElement("span");
      t.textContent = p.label + (p.key === refKey() ? " (reference)" : "") +
        (p.scale > 2 ? " - " + p.scale.toFixed(1) + "x the rest size: zoom out" : "");
      l.appendChild(t);
      labels.appendChild(l);
    });
    draw();
  }

  function draw() {
    if (!panels.length || !panels[0].rect) return;  // before the first layout
    var H = canvas.clientHeight;
    panels.forEach(function (p) {
      var r = p.rect, y = H - r.y - r.h;  // WebGL's origin is the bottom left
      p.light.position.copy(camera.position);
      renderer.setViewport(r.x, y, r.w, r.h);
      renderer.setScissor(r.x, y, r.w, r.h);
      renderer.render(p.scene, camera);
    });
    window.DB_VIEWER_DRAWN++;
  }

  function load(name) {
    var entry = DB_CASES.filter(function (c) { return c.name === name; })[0];
    status.textContent = "loading " + name + " (" + entry.vertices + " vertices)";
    var done = function (rec) {
      status.textContent = rec.vertices + " vertices, " + rec.faces + " faces";
      current = rec;
      build(rec);
    };
    if (DB_MESHES.cases[name]) { DB_MESHES.waiting = null; done(DB_MESHES.cases[name]); return; }
    DB_MESHES.waiting = {name: name, done: done};
    var s = document.createElement("script");
    s.src = entry.file;
    document.body.appendChild(s);
  }

  var select = document.getElementById("case");
  DB_CASES.forEach(function (c) {
    var o = document.createElement("option");
    o.value = c.name; o.textContent = c.name + " (" + c.vertices + " vertices)";
    select.appendChild(o);
  });
  select.addEventListener("change", function () { load(select.value); });
  document.getElementById("ref").addEventListener("change", function () {
    colour(current, decode(current.roles, Uint8Array));
    layout();
  });
  controls.addEventListener("change", draw);
  window.addEventListener("resize", layout);
  if (DB_CASES.length) load(DB_CASES[0].name);
})();
