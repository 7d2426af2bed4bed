// The CIMAX replay viewer: replays a run's events (viewer/src/replay.rs describes the
// stream) onto a canvas. Everything it needs is in the page; window.cimax is its API (tests).
"use strict";
(() => {
  const R = JSON.parse(document.getElementById("replay").textContent);
  const H = R.header;
  const N = H.positions.length;
  const K = H.sectors;
  const VERSION = 1;
  if (R.header.version !== VERSION) {
    throw new Error(`replay version ${R.header.version}, this page reads ${VERSION}`);
  }

  // ---- The stream, decoded into columns. ----
  // Per event: time, op, a (robot or index), b (state, colour, sector, or frame number).
  const T = [], OP = [], A = [], B = [];
  // Per frame on air: its event, sender, bytes, and its exceptions (neighbour index, code).
  const F = { ev: [], from: [], len: [], exc0: [], excN: [] };
  const EXC_J = [], EXC_CODE = [];
  {
    const ev = R.ev;
    let t = 0;
    for (let i = 0; i < ev.length;) {
      t += ev[i];
      const op = ev[i + 1];
      i += 2;
      let a = ev[i++], b = 0;
      if (op === 3) {
        const len = ev[i++], n = ev[i++];
        b = F.ev.length;
        F.ev.push(T.length); F.from.push(a); F.len.push(len);
        F.exc0.push(EXC_J.length); F.excN.push(n);
        for (let k = 0; k < n; k++) { EXC_J.push(ev[i++]); EXC_CODE.push(ev[i++]); }
      } else if (op === 4 || op === 5) {
        b = ev[i++];
      }
      T.push(t); OP.push(op); A.push(a); B.push(b);
    }
  }
  const E = T.length;
  // Per robot, its decisions in time order (indices into R.decisions).
  const decisionsOf = Array.from({ length: N }, () => []);
  R.decisions.forEach((d, k) => decisionsOf[d.robot].push(k));
  const END = Math.max(H.duration_ms, E ? T[E - 1] : 0);
  const FRAME_T = F.ev.map((e) => T[e]);

  // ---- The state at the cursor: everything up to event `cursor` applied. ----
  const fresh = () => ({
    wave: new Int8Array(N), led: new Int16Array(N), pref: new Int16Array(N).fill(-1),
    dec: new Int32Array(N).fill(-1), dead: new Uint8Array(N), pattern: 0, move: -1,
  });
  let S = fresh();
  let cursor = 0;
  const copy = (s) => ({
    wave: s.wave.slice(), led: s.led.slice(), pref: s.pref.slice(), dec: s.dec.slice(),
    dead: s.dead.slice(), pattern: s.pattern, move: s.move,
  });
  const apply = (e) => {
    const a = A[e];
    switch (OP[e]) {
      case 0: case 1: case 2: S.wave[a] = OP[e]; break;
      case 4: S.led[a] = B[e]; break;
      case 5: S.pref[a] = B[e]; break;
      case 6: S.dec[R.decisions[a].robot] = a; break;
      case 7: S.move = a; break;
      case 8: S.dead[a] = 1; S.wave[a] = 0; break;
      case 9: S.dead[a] = 0; break;
      case 10: S.pattern = a; break;
    }
  };
  // Snapshots every CHECK events, so that going back in time replays at most CHECK events.
  const CHECK = 4096;
  const checkpoints = [copy(S)];
  for (let e = 0; e < E; e++) {
    apply(e);
    if ((e + 1) % CHECK === 0) checkpoints.push(copy(S));
  }
  S = fresh();
  // The first event after time t.
  const upper = (arr, t) => {
    let lo = 0, hi = arr.length;
    while (lo < hi) { const m = (lo + hi) >> 1; if (arr[m] <= t) lo = m + 1; else hi = m; }
    return lo;
  };
  const moveTo = (target) => {
    if (target < cursor) {
      const c = Math.floor(target / CHECK);
      S = copy(checkpoints[c]);
      cursor = c * CHECK;
    }
    while (cursor < target) apply(cursor++);
  };

  // ---- Geometry: world (R) to canvas pixels. ----
  const arena = document.getElementById("arena");
  const ctx = arena.getContext("2d");
  const centreAt = () => (S.move >= 0 ? R.moves[S.move].to : H.start);
  const world = (() => {
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    const add = (x, y) => { x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y); };
    const centres = [H.start, ...R.moves.map((m) => m.to)];
    for (const c of centres) for (const p of H.positions) add(c[0] + p[0], c[1] + p[1]);
    if (H.field) {
      const f = H.field;
      add(f.x0, f.y0); add(f.x0 + (f.nx - 1) * f.step, f.y0 + (f.ny - 1) * f.step);
    }
    const pad = H.kind === "line" ? 0.6 : 0.3;
    return { x0: x0 - pad, x1: x1 + pad, y0: y0 - pad, y1: y1 + pad };
  })();
  const view = (() => {
    const w = arena.width, h = arena.height, m = 30;
    const sx = (w - 2 * m) / Math.max(world.x1 - world.x0, 1e-9);
    const sy = (h - 2 * m) / Math.max(world.y1 - world.y0, 1e-9);
    const s = Math.min(sx, sy);
    const ox = (w - s * (world.x1 - world.x0)) / 2, oy = (h - s * (world.y1 - world.y0)) / 2;
    return { s, px: (x) => ox + (x - world.x0) * s, py: (y) => h - oy - (y - world.y0) * s };
  })();
  const where = (i) => {
    const c = centreAt(), p = H.positions[i];
    return [view.px(c[0] + p[0]), view.py(c[1] + p[1])];
  };
  // The robots' radius in pixels: a third of the median distance to the nearest robot (so
  // neighbours do not overlap), within 2..16. At most 2000 robots are measured.
  const radius = (() => {
    const P = H.positions, nearest = [];
    for (let i = 0; i < N; i += Math.ceil(N / 2000)) {
      let d = Infinity;
      for (let j = 0; j < N; j++) {
        if (j !== i) d = Math.min(d, Math.hypot(P[i][0] - P[j][0], P[i][1] - P[j][1]));
      }
      if (Number.isFinite(d)) nearest.push(d);
    }
    nearest.sort((a, b) => a - b);
    const d = nearest.length ? nearest[nearest.length >> 1] : 1;
    return Math.max(2, Math.min(16, (d * view.s) / 3));
  })();

  // ---- Colours. ----
  const OFF = "#c8c8c8", GREEN = "#2e9d4a", BLUE = "#2b6cd6";
  // Sector hues start at 40° so that no sector reads as the refractory ring's red.
  const sectorColour = (s) => `hsl(${Math.round(40 + (300 * s) / Math.max(K - 1, 1))}, 70%, 42%)`;
  const ledColour = (c) => (c === 1 ? GREEN : c === 2 ? BLUE : c >= 10 ? sectorColour(c - 10) : OFF);
  const ledLetter = (c) => (c === 1 ? "L" : c === 2 ? "R" : c >= 10 ? String(c - 10) : "-");
  const WAVE = ["#9a9a9a", "#f0a030", "#d04040"];
  const WAVE_NAME = ["inactive", "active", "refractory"];
  const OUTCOME = ["", "collided", "corrupted", "lost", "receiver transmitting", "receiver dead"];
  const number = (x) => (Math.abs(x) >= 100 ? x.toFixed(0) : x.toPrecision(3));
  const sectorName = (s) => (s < 0 ? "none" : K === 2 ? (s === 0 ? "right" : "left") : `sector ${s}`);

  // The field as an image, once.
  const fieldImage = (() => {
    const f = H.field;
    if (!f) return null;
    const c = document.createElement("canvas");
    c.width = f.nx; c.height = f.ny;
    const g = c.getContext("2d"), img = g.createImageData(f.nx, f.ny);
    let lo = Infinity, hi = -Infinity;
    for (const v of f.values) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    const span = hi > lo ? hi - lo : 1;
    for (let j = 0; j < f.ny; j++) {
      for (let i = 0; i < f.nx; i++) {
        const v = (f.values[j * f.nx + i] - lo) / span;
        const k = 4 * ((f.ny - 1 - j) * f.nx + i);
        // Pale blue (low) to pale amber (high): the robots' colours stay readable on top.
        img.data[k] = 215 + 35 * v; img.data[k + 1] = 230 - 10 * v; img.data[k + 2] = 250 - 110 * v;
        img.data[k + 3] = 255;
      }
    }
    g.putImageData(img, 0, 0);
    return { canvas: c, lo, hi };
  })();

  // ---- Drawing. ----
  let now = 0, speed = 100, playing = false, selected = -1;
  const airtime = (len) => len * H.airtime_ms_per_byte;

  function drawField() {
    if (!fieldImage) return;
    const f = H.field, h = f.step / 2;
    const x = view.px(f.x0 - h), y = view.py(f.y0 + (f.ny - 1) * f.step + h);
    ctx.imageSmoothingEnabled = true;
    ctx.drawImage(fieldImage.canvas, x, y, f.nx * f.step * view.s, f.ny * f.step * view.s);
    ctx.fillStyle = "#555"; ctx.font = "11px sans-serif";
    ctx.fillText(`${f.label}: ${fieldImage.lo.toFixed(1)} (blue) to ${fieldImage.hi.toFixed(1)} (amber)`, 8, arena.height - 8);
  }

  function drawGoal() {
    const g = H.goal;
    if (!g) return;
    ctx.save();
    if (g.within != null) {
      ctx.fillStyle = "rgba(46,157,74,0.12)";
      const a = view.px(g.x - g.within), b = view.px(g.x + g.within);
      ctx.fillRect(a, 0, b - a, arena.height);
    }
    ctx.strokeStyle = "#1d7a35"; ctx.setLineDash([6, 4]);
    ctx.beginPath(); ctx.moveTo(view.px(g.x), 0); ctx.lineTo(view.px(g.x), arena.height); ctx.stroke();
    ctx.restore();
  }

  function drawPath() {
    if (!R.moves.length) return;
    // The centre's path, white under black, a dot per move (under the robots: their LEDs
    // stay readable).
    ctx.save();
    const pts = [H.start];
    for (let m = 0; m <= S.move; m++) pts.push(R.moves[m].to);
    for (const [colour, width] of [["#fff", 5], ["#111", 2]]) {
      ctx.strokeStyle = colour; ctx.lineWidth = width;
      ctx.beginPath();
      pts.forEach(([x, y], k) => (k ? ctx.lineTo(view.px(x), view.py(y)) : ctx.moveTo(view.px(x), view.py(y))));
      ctx.stroke();
    }
    ctx.fillStyle = "#111";
    for (const [x, y] of pts) { ctx.beginPath(); ctx.arc(view.px(x), view.py(y), 3, 0, 2 * Math.PI); ctx.fill(); }
    ctx.restore();
  }

  function drawLamps() {
    const p = H.lights[S.pattern];
    if (!p) return;
    for (let i = 0; i < N; i++) {
      const [x, y] = where(i);
      const lit = p.lights[i] === "1";
      ctx.fillStyle = lit ? "#ffd54a" : "#555";
      ctx.strokeStyle = "#333";
      ctx.beginPath(); ctx.arc(x, y - 5 * radius, radius * 0.8, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      if (lit) {
        ctx.fillStyle = "rgba(255,213,74,0.25)";
        ctx.beginPath(); ctx.moveTo(x - radius * 0.8, y - 5 * radius); ctx.lineTo(x - 2.5 * radius, y);
        ctx.lineTo(x + 2.5 * radius, y); ctx.lineTo(x + radius * 0.8, y - 5 * radius); ctx.fill();
      }
      if (p.expected) {
        ctx.fillStyle = "#555"; ctx.font = "11px sans-serif"; ctx.textAlign = "center";
        ctx.fillText(`expect ${p.expected[i]}`, x, y + 2.2 * radius + 10);
      }
    }
    ctx.textAlign = "left";
  }

  // Frames on air: those still on air, and those of the last moment (a quarter second of
  // wall time at the chosen speed), fading. At most 3000.
  function drawFrames() {
    const persist = Math.min(Math.max(250 * speed, 500), 20000);
    const last = upper(FRAME_T, now);
    let first = upper(FRAME_T, now - persist - airtime(64));
    first = Math.max(first, last - 3000);
    ctx.save();
    for (let f = first; f < last; f++) {
      const t0 = FRAME_T[f], end = t0 + airtime(F.len[f]);
      const age = Math.max(0, now - end);
      if (age > persist) continue;
      const alpha = end > now ? 0.9 : 0.6 * (1 - age / persist);
      const s = F.from[f], [sx, sy] = where(s), nb = R.neighbours[s];
      const bad = new Map();
      for (let k = 0; k < F.excN[f]; k++) bad.set(EXC_J[F.exc0[f] + k], EXC_CODE[F.exc0[f] + k]);
      for (let j = 0; j < nb.length; j++) {
        const [rx, ry] = where(nb[j]);
        ctx.globalAlpha = alpha;
        ctx.strokeStyle = bad.has(j) ? "#d04040" : "#666";
        ctx.lineWidth = end > now ? 2 : 1;
        ctx.beginPath(); ctx.moveTo(sx, sy); ctx.lineTo(rx, ry); ctx.stroke();
        if (bad.has(j)) {
          const mx = sx + 0.8 * (rx - sx), my = sy + 0.8 * (ry - sy), d = Math.max(3, radius / 2);
          ctx.beginPath(); ctx.moveTo(mx - d, my - d); ctx.lineTo(mx + d, my + d);
          ctx.moveTo(mx - d, my + d); ctx.lineTo(mx + d, my - d); ctx.stroke();
        }
      }
    }
    ctx.restore();
  }

  function drawRobots() {
    for (let i = 0; i < N; i++) {
      const [x, y] = where(i);
      ctx.lineWidth = Math.max(0.75, radius / 4);
      ctx.strokeStyle = S.dead[i] ? "#000" : WAVE[S.wave[i]];
      ctx.fillStyle = S.dead[i] ? "#fff" : ledColour(S.led[i]);
      ctx.beginPath(); ctx.arc(x, y, radius, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      if (radius >= 6 && !S.dead[i]) {
        // The K sectors as ticks at the rim; the preferred one long and dark.
        for (let s = 0; s < K; s++) {
          const a = (2 * Math.PI * s) / K, pref = S.pref[i] === s;
          const r0 = radius * (pref ? 0.45 : 0.7), r1 = radius * (pref ? 1.6 : 1.0);
          ctx.strokeStyle = pref ? "#111" : "rgba(255,255,255,0.8)";
          ctx.lineWidth = pref ? 2 : 1;
          ctx.beginPath(); ctx.moveTo(x + r0 * Math.cos(a), y - r0 * Math.sin(a));
          ctx.lineTo(x + r1 * Math.cos(a), y - r1 * Math.sin(a)); ctx.stroke();
        }
      }
      if (S.dead[i]) {
        ctx.strokeStyle = "#000"; ctx.lineWidth = 1.5;
        ctx.beginPath(); ctx.moveTo(x - radius, y - radius); ctx.lineTo(x + radius, y + radius); ctx.stroke();
      }
      if (i === selected) {
        ctx.strokeStyle = "#000"; ctx.lineWidth = 1; ctx.setLineDash([3, 2]);
        ctx.beginPath(); ctx.arc(x, y, radius + 5, 0, 2 * Math.PI); ctx.stroke(); ctx.setLineDash([]);
      }
      if (N <= 16) {
        ctx.fillStyle = "#222"; ctx.font = "11px sans-serif"; ctx.textAlign = "center";
        ctx.fillText(`${i}`, x, y + radius + 12);
        ctx.textAlign = "left";
      }
    }
  }

  // How long drawing takes (a frame at 60 fps has 16.7 ms).
  const drawn = { frames: 0, total: 0, max: 0 };
  function draw() {
    const t0 = performance.now();
    ctx.clearRect(0, 0, arena.width, arena.height);
    drawField();
    drawGoal();
    drawLamps();
    drawFrames();
    drawPath();
    drawRobots();
    drawChart();
    showRobot();
    slider.value = String(Math.round((1000 * now) / Math.max(END, 1)));
    clock.textContent = `${(now / 1000).toFixed(1)} s / ${(END / 1000).toFixed(0)} s`;
    const dt = performance.now() - t0;
    drawn.frames++; drawn.total += dt; drawn.max = Math.max(drawn.max, dt);
  }

  // ---- The chart: consensus and diversity against time, with the cursor. ----
  const chart = document.getElementById("chart");
  const cg = chart.getContext("2d");
  const chartX = (t) => 40 + ((chart.width - 50) * t) / Math.max(END, 1);
  function drawChart() {
    const w = chart.width, h = chart.height, top = 10, bottom = h - 20;
    cg.clearRect(0, 0, w, h);
    cg.strokeStyle = "#ccc"; cg.strokeRect(40, top, w - 50, bottom - top);
    const s = R.series, dmax = s.diversity.reduce((a, b) => Math.max(a, b), 1e-9);
    const line = (vals, scale, colour) => {
      cg.strokeStyle = colour; cg.lineWidth = 1.5; cg.beginPath();
      let y = bottom;
      cg.moveTo(chartX(0), y);
      for (let k = 0; k < s.t_ms.length; k++) {
        const x = chartX(s.t_ms[k]);
        cg.lineTo(x, y);
        y = bottom - ((bottom - top) * vals[k]) / scale;
        cg.lineTo(x, y);
      }
      cg.lineTo(chartX(END), y); cg.stroke();
    };
    line(s.consensus, 1, "#1d7a35");
    line(s.diversity, dmax, "#8a4fd6");
    for (const m of R.moves) {
      cg.fillStyle = "#999"; cg.fillRect(chartX(m.t_ms), bottom, 1, 5);
    }
    cg.strokeStyle = "#000"; cg.beginPath(); cg.moveTo(chartX(now), top); cg.lineTo(chartX(now), bottom); cg.stroke();
    cg.fillStyle = "#1d7a35"; cg.font = "11px sans-serif";
    cg.fillText(H.lights.some((p) => p.expected) ? "share of LEDs as expected (0–1)" : "consensus: share showing the most shown decision (0–1)", 45, h - 5);
    cg.fillStyle = "#8a4fd6";
    cg.fillText(`diversity: best sector's score, mean over robots (max ${number(dmax)})`, 380, h - 5);
    cg.fillStyle = "#555";
    cg.fillText("1", 28, top + 8); cg.fillText("0", 28, bottom);
  }

  // ---- The robot panel. ----
  const panel = document.getElementById("robot");
  function showRobot() {
    if (selected < 0) return;
    const i = selected, d = S.dec[i] >= 0 ? R.decisions[S.dec[i]] : null;
    const readings = decisionsOf[i].filter((k) => k <= S.dec[i]).map((k) => R.decisions[k].reading);
    const rows = [];
    for (let s = 0; s < K; s++) {
      const sc = d && d.scores[s] != null ? number(d.scores[s]) : "–";
      rows.push(`<tr><th>${sectorName(s)}</th><td>${sc}</td><td>${d && d.votes.length ? d.votes[s] : "–"}</td></tr>`);
    }
    const p = H.positions[i], c = centreAt();
    panel.innerHTML =
      `<p>robot ${i}: id ${H.ids[i]}, tag ${H.ids[i] % 16}, at (${(c[0] + p[0]).toFixed(2)}, ${(c[1] + p[1]).toFixed(2)}) R<br>` +
      `wave ${S.dead[i] ? "dead" : WAVE_NAME[S.wave[i]]}, LEDs ${ledLetter(S.led[i])}, prefers ${sectorName(S.pref[i])}<br>` +
      (d ? `decision of period ${d.period}: <b>${sectorName(d.decision)}</b>` : "no decision yet") + `</p>` +
      `<table><tr><th>sector</th><th>score</th><th>votes</th></tr>${rows.join("")}</table>` +
      `<p>readings at its decisions: ${readings.slice(-12).join(", ") || "–"}</p>`;
  }
  arena.addEventListener("click", (ev) => {
    const r = arena.getBoundingClientRect();
    const x = ((ev.clientX - r.left) * arena.width) / r.width, y = ((ev.clientY - r.top) * arena.height) / r.height;
    let best = -1, bd = Infinity;
    for (let i = 0; i < N; i++) {
      const [px, py] = where(i), d = Math.hypot(px - x, py - y);
      if (d < bd) { bd = d; best = i; }
    }
    select(bd <= radius + 6 ? best : -1);
  });
  function select(i) {
    selected = i;
    if (i < 0) panel.textContent = "Click a robot.";
    draw();
  }

  // ---- Time: seek, play, step. ----
  const slider = document.getElementById("slider");
  const clock = document.getElementById("clock");
  const playButton = document.getElementById("play");
  function seek(t) {
    now = Math.max(0, Math.min(END, t));
    moveTo(upper(T, now));
    draw();
  }
  let lastWall = 0, endWaiters = [];
  function tick(wall) {
    if (!playing) return;
    const dt = lastWall ? wall - lastWall : 0;
    lastWall = wall;
    seek(now + dt * speed);
    if (now >= END) {
      pause();
      endWaiters.forEach((f) => f());
      endWaiters = [];
      return;
    }
    requestAnimationFrame(tick);
  }
  function play(s) {
    if (s) setSpeed(s);
    if (now >= END) seek(0);
    playing = true; lastWall = 0; playButton.textContent = "❚❚";
    requestAnimationFrame(tick);
  }
  function pause() { playing = false; playButton.textContent = "▶"; }
  function setSpeed(s) {
    speed = Number(s);
    document.getElementById("speed").value = String(speed);
  }
  // One frame on air on (or back): the next one's start.
  function step(dir) {
    pause();
    const f = dir > 0 ? upper(FRAME_T, now) : upper(FRAME_T, now - 1e-6) - 2;
    if (f >= 0 && f < FRAME_T.length) seek(FRAME_T[f] + 1e-3);
    else seek(dir > 0 ? END : 0);
  }
  playButton.addEventListener("click", () => (playing ? pause() : play()));
  document.getElementById("back").addEventListener("click", () => step(-1));
  document.getElementById("fwd").addEventListener("click", () => step(1));
  document.getElementById("speed").addEventListener("change", (e) => setSpeed(e.target.value));
  slider.addEventListener("input", () => seek((Number(slider.value) * END) / 1000));
  chart.addEventListener("click", (ev) => {
    const r = chart.getBoundingClientRect();
    const x = ((ev.clientX - r.left) * chart.width) / r.width;
    seek(((x - 40) / (chart.width - 50)) * END);
  });
  document.addEventListener("keydown", (e) => {
    if (e.key === " ") { e.preventDefault(); playing ? pause() : play(); }
    if (e.key === "ArrowRight") step(1);
    if (e.key === "ArrowLeft") step(-1);
  });

  // The LEDs as drawn: the colour of the pixel at each robot's centre, named.
  function ledsDrawn() {
    const names = [[OFF, "-"], [GREEN, "L"], [BLUE, "R"]];
    for (let s = 0; s < K && K > 2; s++) names.push([sectorColour(s), String(s)]);
    const probe = document.createElement("canvas").getContext("2d");
    const rgb = names.map(([c, n]) => {
      probe.fillStyle = c; probe.fillRect(0, 0, 1, 1);
      return [probe.getImageData(0, 0, 1, 1).data, n];
    });
    let out = "";
    for (let i = 0; i < N; i++) {
      const [x, y] = where(i);
      const px = ctx.getImageData(Math.round(x), Math.round(y), 1, 1).data;
      let best = "?", bd = Infinity;
      for (const [c, n] of rgb) {
        const d = Math.abs(c[0] - px[0]) + Math.abs(c[1] - px[1]) + Math.abs(c[2] - px[2]);
        if (d < bd) { bd = d; best = n; }
      }
      out += bd < 30 ? best : "?";
    }
    return out;
  }

  // ---- Start. ----
  if (K > 2) {
    // LEDs show a sector: one swatch per sector instead of green and blue.
    const legend = document.getElementById("legend");
    legend.querySelectorAll(".led").forEach((li) => li.remove());
    for (let s = K - 1; s >= 0; s--) {
      const li = document.createElement("li");
      li.innerHTML = `<span class="sw" style="background:${sectorColour(s)}"></span>LEDs: sector ${s} (${Math.round((360 * s) / K)}°)`;
      legend.prepend(li);
    }
  }
  if (!H.lights.length) document.querySelector("#legend .lamp")?.remove();
  const v = H.verdict, verdict = document.getElementById("verdict");
  if (v) {
    verdict.textContent = v.text;
    verdict.className = v.success ? "pass" : "fail";
  }
  seek(R.open_at_ms || 0);
  if (R.open_robot != null) select(R.open_robot);
  window.cimax = {
    duration: END,
    robots: N,
    time: () => now,
    seek, play, pause, step, select,
    speed: () => speed,
    playToEnd(s) {
      return new Promise((resolve) => { endWaiters.push(resolve); play(s || 10000); });
    },
    leds: () => Array.from(S.led, ledLetter).join(""),
    ledsDrawn,
    frames: F.ev.length,
    // Drawing cost so far: frames drawn, mean and worst ms per frame.
    drawStats: () => ({ frames: drawn.frames, mean_ms: drawn.total / Math.max(drawn.frames, 1), max_ms: drawn.max }),
  };
})();
