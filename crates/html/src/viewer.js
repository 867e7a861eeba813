// linkage 3-D view: a small canvas-2D software renderer (painter's algorithm, flat shading).
// Scene data: the JSON in #scene-data (meshes in body frames, part poses per frame).
// Writes its state into #status: "ok frames=F items=I triangles=T drawn_pixels=P" after the
// first frame is drawn, or "error: …" when a script fails (window.onerror, set earlier).
(function () {
  "use strict";
  var S = JSON.parse(document.getElementById("scene-data").textContent);
  var canvas = document.getElementById("view");
  var ctx = canvas.getContext("2d");
  var BG = [250, 250, 252];
  var status = document.getElementById("status");
  var slider = document.getElementById("frame");
  var play = document.getElementById("play");
  var clock = document.getElementById("clock");
  var choice = document.getElementById("anim");
  var anim = 0, frame = 0, playing = false, last = 0;

  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function add(a, b) { return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]; }
  function mul(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function cross(a, b) {
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  }
  function unit(a) { var n = Math.sqrt(dot(a, a)) || 1; return mul(a, 1 / n); }
  // Rotates v by the unit quaternion (w, x, y, z) at q[o+3..o+7].
  function rotate(q, o, v) {
    var w = q[o + 3], x = q[o + 4], y = q[o + 5], z = q[o + 6];
    var t = mul(cross([x, y, z], v), 2);
    return add(add(v, mul(t, w)), cross([x, y, z], t));
  }
  function place(pose, body, v) {
    if (body < 0 || !pose) return v;
    var o = body * 7;
    return add(rotate(pose, o, v), [pose[o], pose[o + 1], pose[o + 2]]);
  }
  function pose(a, f) {
    var A = S.anims[a];
    return A && A.poses.length ? A.poses[Math.min(f, A.poses.length - 1)] : null;
  }
  // Every vertex of every item in ground at a frame.
  function worldVertices(p) {
    return S.items.map(function (it) {
      var out = [];
      for (var k = 0; k < it.p.length; k += 3) {
        var b = it.vb ? it.vb[k / 3] : it.b;
        out.push(place(p, b, [it.p[k], it.p[k + 1], it.p[k + 2]]));
      }
      return out;
    });
  }

  // Camera: orbit about the centre of the first frame's bounding box, around the up axis.
  var first = worldVertices(pose(0, 0));
  var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  first.forEach(function (vs) {
    vs.forEach(function (v) {
      for (var i = 0; i < 3; i++) { lo[i] = Math.min(lo[i], v[i]); hi[i] = Math.max(hi[i], v[i]); }
    });
  });
  if (!(lo[0] <= hi[0])) { lo = [-1, -1, -1]; hi = [1, 1, 1]; }
  var centre = mul(add(lo, hi), 0.5);
  var radius = Math.max(Math.sqrt(dot(sub(hi, lo), sub(hi, lo))) * 0.5, 1e-9);
  var up = unit(S.up), e1 = unit(S.across), e2 = cross(up, e1);
  var yaw = 0.35, pitch = 0.3, dist = radius * 2.3;

  function camera() {
    var d = add(mul(add(mul(e1, Math.cos(yaw)), mul(e2, Math.sin(yaw))), Math.cos(pitch)),
      mul(up, Math.sin(pitch)));
    var eye = add(centre, mul(d, dist));
    var fwd = mul(d, -1);
    var right = unit(cross(fwd, up));
    var cup = cross(right, fwd);
    return { eye: eye, fwd: fwd, right: right, up: cup };
  }

  function rgb(c, s) {
    return "rgb(" + Math.round(c[0] * s) + "," + Math.round(c[1] * s) + "," + Math.round(c[2] * s) + ")";
  }

  var triangles = 0;
  function draw() {
    var W = canvas.width, H = canvas.height;
    ctx.fillStyle = rgb(BG, 1);
    ctx.fillRect(0, 0, W, H);
    var cam = camera(), f = 0.5 * Math.min(W, H) / Math.tan(0.35), near = radius * 1e-3;
    var world = worldVertices(pose(anim, frame));
    var prims = [];
    triangles = 0;
    S.items.forEach(function (it, n) {
      var cv = world[n].map(function (v) {
        var r = sub(v, cam.eye);
        return [dot(r, cam.right), dot(r, cam.up), dot(r, cam.fwd)];
      });
      var sv = cv.map(function (c) { return [W / 2 + f * c[0] / c[2], H / 2 - f * c[1] / c[2]]; });
      for (var k = 0; k < it.t.length; k += 3) {
        var a = cv[it.t[k]], b = cv[it.t[k + 1]], c = cv[it.t[k + 2]];
        if (a[2] < near || b[2] < near || c[2] < near) continue;
        var nrm = unit(cross(sub(b, a), sub(c, a)));
        var shade = 0.45 + 0.55 * Math.abs(nrm[2] * 0.8 + nrm[1] * 0.4 + nrm[0] * 0.2);
        prims.push({ z: (a[2] + b[2] + c[2]) / 3, pts: [sv[it.t[k]], sv[it.t[k + 1]], sv[it.t[k + 2]]],
          fill: rgb(it.c, Math.min(shade, 1)) });
        triangles++;
      }
      for (var j = 0; j < it.l.length; j += 2) {
        var p = cv[it.l[j]], q = cv[it.l[j + 1]];
        if (p[2] < near || q[2] < near) continue;
        prims.push({ z: (p[2] + q[2]) / 2 - radius * 1e-3, pts: [sv[it.l[j]], sv[it.l[j + 1]]],
          stroke: rgb(it.c, it.t.length ? 0.6 : 1) });
      }
    });
    prims.sort(function (a, b) { return b.z - a.z; });
    ctx.lineWidth = 1;
    prims.forEach(function (p) {
      ctx.beginPath();
      ctx.moveTo(p.pts[0][0], p.pts[0][1]);
      for (var i = 1; i < p.pts.length; i++) ctx.lineTo(p.pts[i][0], p.pts[i][1]);
      if (p.fill) {
        ctx.closePath();
        ctx.fillStyle = p.fill; ctx.strokeStyle = p.fill;
        ctx.fill(); ctx.stroke();
      } else {
        ctx.strokeStyle = p.stroke; ctx.lineWidth = 1.5; ctx.stroke(); ctx.lineWidth = 1;
      }
    });
    var A = S.anims[anim];
    if (A && A.times.length) {
      clock.textContent = A.label + " " + A.times[Math.min(frame, A.times.length - 1)].toPrecision(5) +
        " (frame " + (frame + 1) + " of " + A.times.length + ")";
    }
  }

  function drawnPixels() {
    var d = ctx.getImageData(0, 0, canvas.width, canvas.height).data, n = 0;
    for (var i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i] - BG[0]) + Math.abs(d[i + 1] - BG[1]) + Math.abs(d[i + 2] - BG[2]) > 24) n++;
    }
    return n;
  }

  function frames() { var A = S.anims[anim]; return A ? A.times.length : 1; }
  function setAnim(a) {
    anim = a; frame = 0;
    slider.max = Math.max(frames() - 1, 0); slider.value = 0;
    draw();
  }
  slider.addEventListener("input", function () { frame = +slider.value; draw(); });
  play.addEventListener("click", function () {
    playing = !playing; play.textContent = playing ? "pause" : "play";
    if (playing) requestAnimationFrame(tick);
  });
  if (choice) choice.addEventListener("change", function () { setAnim(+choice.value); });
  function tick(t) {
    if (!playing) return;
    if (t - last > 33) {
      last = t;
      frame = (frame + 1) % frames();
      slider.value = frame;
      draw();
    }
    requestAnimationFrame(tick);
  }
  var drag = null;
  canvas.addEventListener("mousedown", function (e) { drag = [e.clientX, e.clientY]; });
  window.addEventListener("mouseup", function () { drag = null; });
  window.addEventListener("mousemove", function (e) {
    if (!drag) return;
    yaw -= (e.clientX - drag[0]) * 0.01;
    pitch = Math.max(-1.55, Math.min(1.55, pitch + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw();
  });
  canvas.addEventListener("wheel", function (e) {
    e.preventDefault();
    dist *= Math.exp(e.deltaY * 0.001);
    draw();
  }, { passive: false });

  setAnim(0);
  if (!window.__linkageErrors.length) {
    status.textContent = "ok frames=" + frames() + " items=" + S.items.length +
      " triangles=" + triangles + " drawn_pixels=" + drawnPixels();
  }
})();
