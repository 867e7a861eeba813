// linkage 3-D view: a small canvas-2D software renderer (painter's algorithm, flat shading).
// Scene data: the JSON in #scene-data (meshes in body frames, part poses per frame).
// Writes its state into the hidden #status: "ok frames=F items=I triangles=T drawn_pixels=P
// verdict_bottom=Y first_plot_top=Y" after the first frame is drawn (and " cursor=X" once the
// slider has moved a plot's time cursor), or "error: …" when a script fails (window.onerror).
// The address may carry "#paused" (no autoplay), "frame=K" (the slider moved to output K) and
// "hide=NAME" (a click on that part's entry in the parts list); the status then ends with
// " hidden=H" (items hidden).
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
  var autoplay = document.getElementById("autoplay");
  var partsBox = document.getElementById("parts");
  var plots = Array.prototype.slice.call(document.querySelectorAll("svg.plot[data-t0]"));
  var anim = 0, frame = 0, playing = false, last = 0;
  var hash = location.hash.replace(/^#/, "").split("&");
  function hashValue(key) {
    for (var i = 0; i < hash.length; i++) {
      var kv = hash[i].split("=");
      if (kv[0] === key) return kv.length > 1 ? kv[1] : "";
    }
    return null;
  }

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

  // Display of each item: 0 shown, 1 transparent, 2 hidden.
  var display = S.items.map(function () { return 0; });
  function moving(it) {
    if (it.vb) return it.vb.some(function (b) { return b >= 0; });
    return it.b >= 0;
  }

  // Framing: each item's box over frames sampled through the first animation (a turning
  // blade sweeps beyond its first pose). A solid whose surface (half its triangles' area:
  // one side of a plate) is at least LARGE_AREA of the whole scene's box (its two largest
  // sides) — a windshield over a wiper mechanism, a base plate — starts transparent and does
  // not set the view.
  var A0 = S.anims[0];
  var nframes = A0 && A0.poses.length ? A0.poses.length : 1;
  var vertexCount = S.items.reduce(function (n, it) { return n + it.p.length / 3; }, 0);
  var samples = Math.max(1, Math.min(40, nframes, Math.floor(2e6 / Math.max(vertexCount, 1))));
  function emptyBox() { return { lo: [Infinity, Infinity, Infinity], hi: [-Infinity, -Infinity, -Infinity] }; }
  function grow(into, bx) {
    for (var i = 0; i < 3; i++) { into.lo[i] = Math.min(into.lo[i], bx.lo[i]); into.hi[i] = Math.max(into.hi[i], bx.hi[i]); }
  }
  var boxes = S.items.map(emptyBox), firstBoxes = S.items.map(emptyBox);
  for (var s = 0; s < samples; s++) {
    var f = samples > 1 ? Math.round(s * (nframes - 1) / (samples - 1)) : 0;
    worldVertices(pose(0, f)).forEach(function (vs, n) {
      vs.forEach(function (v) {
        grow(boxes[n], { lo: v, hi: v });
        if (s === 0) grow(firstBoxes[n], { lo: v, hi: v });
      });
    });
  }
  function diagonal(bx) { var d = sub(bx.hi, bx.lo); return bx.lo[0] <= bx.hi[0] ? Math.sqrt(dot(d, d)) : 0; }
  // The product of the two largest sides of a box.
  function area(bx) {
    if (!(bx.lo[0] <= bx.hi[0])) return 0;
    var d = sub(bx.hi, bx.lo).map(Math.abs).sort(function (a, b) { return b - a; });
    return d[0] * d[1];
  }
  var LARGE_AREA = 0.4;
  // (At the first frame: a part's sweep over the run is not its size.)
  var scene = emptyBox();
  firstBoxes.forEach(function (bx) { if (bx.lo[0] <= bx.hi[0]) grow(scene, bx); });
  var firstWorld = worldVertices(pose(0, 0));
  function surface(it, vs) {
    var sum = 0;
    for (var k = 0; k < it.t.length; k += 3) {
      var a = vs[it.t[k]], b = vs[it.t[k + 1]], c = vs[it.t[k + 2]];
      var x = cross(sub(b, a), sub(c, a));
      sum += 0.5 * Math.sqrt(dot(x, x));
    }
    return 0.5 * sum;
  }
  if (S.items.length >= 3 && area(scene) > 0) {
    S.items.forEach(function (it, n) {
      if (it.t.length && surface(it, firstWorld[n]) >= LARGE_AREA * area(scene)) display[n] = 1;
    });
  }
  var frame0 = emptyBox();
  boxes.forEach(function (bx, n) { if (display[n] === 0 && bx.lo[0] <= bx.hi[0]) grow(frame0, bx); });
  if (!(frame0.lo[0] <= frame0.hi[0])) boxes.forEach(function (bx) { if (bx.lo[0] <= bx.hi[0]) grow(frame0, bx); });
  var lo = frame0.lo, hi = frame0.hi;
  if (!(lo[0] <= hi[0])) { lo = [-1, -1, -1]; hi = [1, 1, 1]; }
  var centre = mul(add(lo, hi), 0.5);
  var radius = Math.max(Math.sqrt(dot(sub(hi, lo), sub(hi, lo))) * 0.5, 1e-9);
  var up = unit(S.up), e1 = unit(S.across), e2 = cross(up, e1);
  var HALF_FOV = 0.35;
  // The bounding sphere fits the smaller side of the canvas, with a margin.
  var yaw = 0.35, pitch = 0.3, dist = 1.08 * radius / Math.sin(HALF_FOV);

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

  var triangles = 0, prims = [];
  function draw() {
    var W = canvas.width, H = canvas.height;
    ctx.globalAlpha = 1;
    ctx.fillStyle = rgb(BG, 1);
    ctx.fillRect(0, 0, W, H);
    var cam = camera(), f = 0.5 * Math.min(W, H) / Math.tan(HALF_FOV), near = radius * 1e-3;
    var world = worldVertices(pose(anim, frame));
    prims = [];
    triangles = 0;
    S.items.forEach(function (it, n) {
      if (display[n] === 2) return;
      var alpha = display[n] === 1 ? 0.18 : 1;
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
          fill: rgb(it.c, Math.min(shade, 1)), alpha: alpha, item: n });
        triangles++;
      }
      for (var j = 0; j < it.l.length; j += 2) {
        var p = cv[it.l[j]], q = cv[it.l[j + 1]];
        if (p[2] < near || q[2] < near) continue;
        prims.push({ z: (p[2] + q[2]) / 2 - radius * 1e-3, pts: [sv[it.l[j]], sv[it.l[j + 1]]],
          stroke: rgb(it.c, it.t.length ? 0.6 : 1), alpha: alpha, item: n });
      }
    });
    prims.sort(function (a, b) { return b.z - a.z; });
    ctx.lineWidth = 1;
    prims.forEach(function (p) {
      ctx.globalAlpha = p.alpha;
      ctx.beginPath();
      ctx.moveTo(p.pts[0][0], p.pts[0][1]);
      for (var i = 1; i < p.pts.length; i++) ctx.lineTo(p.pts[i][0], p.pts[i][1]);
      if (p.fill) {
        ctx.closePath();
        ctx.fillStyle = p.fill; ctx.strokeStyle = p.fill;
        ctx.fill(); if (p.alpha === 1) ctx.stroke();
      } else {
        ctx.strokeStyle = p.stroke; ctx.lineWidth = 1.5; ctx.stroke(); ctx.lineWidth = 1;
      }
    });
    ctx.globalAlpha = 1;
    var A = S.anims[anim];
    if (A && A.times.length) {
      var t = A.times[Math.min(frame, A.times.length - 1)];
      clock.textContent = A.label + " " + t.toPrecision(5) +
        " (frame " + (frame + 1) + " of " + A.times.length + ")";
      moveCursors(t);
    }
  }

  // The time cursor of every plot against time, at time t (hidden outside its axis).
  var cursorX = null;
  function moveCursors(t) {
    plots.forEach(function (svg, k) {
      var t0 = +svg.getAttribute("data-t0"), t1 = +svg.getAttribute("data-t1");
      var left = +svg.getAttribute("data-left"), width = +svg.getAttribute("data-width");
      var line = svg.querySelector("line.cursor");
      if (!line) return;
      var inside = t >= t0 - 1e-9 * Math.abs(t1 - t0) && t <= t1 + 1e-9 * Math.abs(t1 - t0) && t1 > t0;
      var x = left + (Math.min(Math.max(t, t0), t1) - t0) / (t1 - t0 || 1) * width;
      line.setAttribute("x1", x.toFixed(2));
      line.setAttribute("x2", x.toFixed(2));
      line.setAttribute("visibility", inside ? "visible" : "hidden");
      if (k === 0) cursorX = x;
    });
  }

  function drawnPixels() {
    var d = ctx.getImageData(0, 0, canvas.width, canvas.height).data, n = 0;
    for (var i = 0; i < d.length; i += 4) {
      if (Math.abs(d[i] - BG[0]) + Math.abs(d[i + 1] - BG[1]) + Math.abs(d[i + 2] - BG[2]) > 24) n++;
    }
    return n;
  }

  // The parts list: one checkbox per body that has something drawn (ground first).
  var bodyOf = S.items.map(function (it) { return it.b; });
  var boxesOfBody = {};
  function refreshList() {
    Object.keys(boxesOfBody).forEach(function (b) {
      var shown = false;
      S.items.forEach(function (it, n) { if (bodyOf[n] === +b && display[n] !== 2) shown = true; });
      boxesOfBody[b].checked = shown;
    });
  }
  function setBody(b, value) {
    S.items.forEach(function (it, n) { if (bodyOf[n] === b) display[n] = value; });
    refreshList();
    draw();
  }
  (function buildList() {
    var bodies = [];
    bodyOf.forEach(function (b) { if (bodies.indexOf(b) < 0) bodies.push(b); });
    bodies.sort(function (a, b) { return a - b; });
    if (bodies.length > 300) { partsBox.style.display = "none"; return; }
    bodies.forEach(function (b) {
      var label = document.createElement("label");
      var box = document.createElement("input");
      box.type = "checkbox"; box.checked = true;
      box.addEventListener("change", function () { setBody(b, box.checked ? 0 : 2); });
      label.appendChild(box);
      label.appendChild(document.createTextNode(" " + (b < 0 ? "ground" : S.parts[b])));
      partsBox.appendChild(label);
      boxesOfBody[b] = box;
      label.setAttribute("data-part", b < 0 ? "ground" : S.parts[b]);
    });
  })();

  // The item drawn on top at canvas point (x, y), or -1.
  function pick(x, y) {
    for (var i = prims.length - 1; i >= 0; i--) {
      var p = prims[i], q = p.pts;
      if (p.fill) {
        var d1 = (x - q[1][0]) * (q[0][1] - q[1][1]) - (q[0][0] - q[1][0]) * (y - q[1][1]);
        var d2 = (x - q[2][0]) * (q[1][1] - q[2][1]) - (q[1][0] - q[2][0]) * (y - q[2][1]);
        var d3 = (x - q[0][0]) * (q[2][1] - q[0][1]) - (q[2][0] - q[0][0]) * (y - q[0][1]);
        var neg = d1 < 0 || d2 < 0 || d3 < 0, pos = d1 > 0 || d2 > 0 || d3 > 0;
        if (!(neg && pos)) return p.item;
      } else {
        var dx = q[1][0] - q[0][0], dy = q[1][1] - q[0][1], len = dx * dx + dy * dy || 1;
        var u = Math.max(0, Math.min(1, ((x - q[0][0]) * dx + (y - q[0][1]) * dy) / len));
        var ex = q[0][0] + u * dx - x, ey = q[0][1] + u * dy - y;
        if (ex * ex + ey * ey < 16) return p.item;
      }
    }
    return -1;
  }

  function frames() { var A = S.anims[anim]; return A ? A.times.length : 1; }
  function setAnim(a) {
    anim = a; frame = 0;
    slider.max = Math.max(frames() - 1, 0); slider.value = 0;
    draw();
  }
  function setPlaying(on) {
    playing = on && frames() > 1; play.textContent = playing ? "pause" : "play";
    if (playing) requestAnimationFrame(tick);
  }
  slider.addEventListener("input", function () { frame = +slider.value; draw(); });
  play.addEventListener("click", function () { setPlaying(!playing); });
  autoplay.addEventListener("change", function () { setPlaying(autoplay.checked); });
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
  var drag = null, moved = 0;
  canvas.addEventListener("mousedown", function (e) { drag = [e.clientX, e.clientY]; moved = 0; });
  window.addEventListener("mouseup", function (e) {
    if (drag && moved < 4) {
      // A click, not a drag: the part under it goes transparent, then hidden.
      var r = canvas.getBoundingClientRect();
      var n = pick((e.clientX - r.left) * canvas.width / r.width, (e.clientY - r.top) * canvas.height / r.height);
      if (n >= 0) setBody(bodyOf[n], display[n] === 0 ? 1 : 2);
    }
    drag = null;
  });
  window.addEventListener("mousemove", function (e) {
    if (!drag) return;
    moved += Math.abs(e.clientX - drag[0]) + Math.abs(e.clientY - drag[1]);
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
  var paused = hashValue("paused") !== null;
  if (paused) autoplay.checked = false;
  var start = hashValue("frame");
  if (start !== null) {
    // As a user moving the slider.
    slider.value = start;
    slider.dispatchEvent(new Event("input"));
  }
  var toHide = hashValue("hide");
  if (toHide !== null) {
    // As a user clicking the part's entry in the list.
    var entry = partsBox.querySelector('label[data-part="' + decodeURIComponent(toHide) + '"] input');
    if (entry) entry.click();
  }
  if (!window.__linkageErrors.length) {
    var verdict = document.getElementById("verdict");
    var firstPlot = document.querySelector("svg.plot");
    status.textContent = "ok frames=" + frames() + " items=" + S.items.length +
      " triangles=" + triangles + " drawn_pixels=" + drawnPixels() +
      " transparent=" + display.filter(function (d) { return d === 1; }).length +
      (verdict ? " verdict_bottom=" + Math.round(verdict.getBoundingClientRect().bottom) : "") +
      (firstPlot ? " first_plot_top=" + Math.round(firstPlot.getBoundingClientRect().top) : "") +
      (cursorX !== null ? " cursor=" + cursorX.toFixed(2) : "") +
      (toHide !== null ? " hidden=" + display.filter(function (d) { return d === 2; }).length : "");
  }
  if (!paused && autoplay.checked) setPlaying(true);
})();
