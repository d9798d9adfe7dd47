// cellsurf serve: the page. Plain JavaScript, no library, no network beyond this server.
"use strict";

const $ = (id) => document.getElementById(id);
const HEX_ROW = Math.sqrt(3) / 2;
const CONTROLS = ["preset", "lattice", "boundary", "width", "height", "shape", "start",
  "n", "weight", "sampler", "ca_rule", "seed", "speed"];
const COLORS = { empty: [250, 250, 246], surface: [233, 162, 59], occupied: [34, 34, 34],
  border: [214, 214, 208] };

let ws = null;          // the growth session's socket
let info = null;        // the session's settings, from the server
let playing = false;
let presets = [];
let series = [];        // {t, accepted, occupied, surface, acceptance, value, w}
let lastPick = null;    // the explained pick to highlight
let geometry = null;    // pixel -> cell map of the lattice canvas
let lastFrame = null;
let pendingScenario = false;

// ---------- URL <-> controls ----------
function queryParams() {
  const p = new URLSearchParams(location.search);
  const out = {};
  for (const [k, v] of p) out[k] = v;
  return out;
}

function nFromSlider(s) { return s <= -2 ? 0 : Math.round(Math.pow(10, s) * 1000) / 1000; }
function sliderFromN(n) { return n <= 0 ? -2.05 : Math.log10(n); }
function speedFromSlider(s) { return Math.round(Math.pow(10, s)); }

function setControls(c) {
  for (const k of CONTROLS) {
    if (c[k] === undefined || !$(k)) continue;
    $(k).value = c[k];
  }
  if (c.n !== undefined) { $("nlog").value = sliderFromN(Number(c.n)); $("nval").textContent = c.n; }
  if (c.speed !== undefined) { $("speedlog").value = Math.log10(Number(c.speed)); $("speedval").textContent = c.speed; }
}

// The settings that differ from the preset's, plus the preset.
function currentQuery(extra) {
  const q = new URLSearchParams();
  q.set("preset", $("preset").value);
  const base = info && info.defaults ? info.defaults : {};
  for (const k of CONTROLS) {
    if (k === "preset") continue;
    const v = $(k).value;
    if (v === "" || v === undefined) continue;
    if (base[k] !== undefined && String(base[k]) === String(v)) continue;
    q.set(k, v);
  }
  for (const k in (extra || {})) q.set(k, extra[k]);
  return q;
}

function linkOf(extra) {
  return location.origin + "/?" + currentQuery(extra).toString();
}

// ---------- connection ----------
function connect(query) {
  if (ws) { ws.onclose = null; ws.close(); }
  series = []; lastPick = null; geometry = null;
  $("status").textContent = "connecting";
  const proto = location.protocol === "https:" ? "wss:" : "ws:";
  ws = new WebSocket(proto + "//" + location.host + "/ws/growth?" + query.toString());
  ws.binaryType = "arraybuffer";
  ws.onmessage = (ev) => {
    if (typeof ev.data !== "string") { drawFrame(new Uint8Array(ev.data)); return; }
    const m = JSON.parse(ev.data);
    if (m.type === "info") onInfo(m);
    else if (m.type === "stats") onStats(m);
    else if (m.type === "pick") onPick(m.explained);
    else if (m.type === "scenario") onScenario(m.toml);
    else if (m.type === "error") $("status").textContent = "error: " + m.message;
  };
  ws.onclose = () => { $("status").textContent = "disconnected"; setPlaying(false); };
  ws.onerror = () => {
    // The settings were refused: ask the check endpoint why.
    fetch("/api/check?" + query.toString()).then((r) => r.json()).then((j) => {
      if (j.error) $("status").textContent = "error: " + j.error;
    });
  };
}

function send(cmd) { if (ws && ws.readyState === 1) ws.send(JSON.stringify(cmd)); }

function onInfo(m) {
  info = m;
  setControls({ preset: m.preset.split("+")[0], lattice: m.lattice, boundary: m.boundary,
    width: m.width, height: m.height, shape: m.shape, start: m.start, n: m.n,
    weight: m.weight, sampler: m.sampler, ca_rule: m.ca_rule, seed: m.seed, speed: m.speed });
  $("status").textContent = "ready";
  $("linktext").value = linkOf();
  if (queryParams().autoplay === "1" && !playing) togglePlay();
  if (queryParams().explain === "1") send({ cmd: "explain" });
}

function fmt(x, d) {
  if (x === null || x === undefined || Number.isNaN(x)) return "-";
  if (Math.abs(x) >= 1e6) return x.toExponential(3);
  return Number.isInteger(x) ? String(x) : x.toFixed(d === undefined ? 4 : d);
}

function onStats(m) {
  $("steps").textContent = fmt(m.time);
  $("accepted").textContent = String(m.accepted);
  $("occupied").textContent = String(m.occupied);
  $("surface").textContent = String(m.surface);
  $("acceptance").textContent = fmt(m.acceptance);
  $("obsname").textContent = m.observable;
  $("obscaption").textContent = m.observable + " against timesteps";
  $("obsval").textContent = fmt(m.value);
  $("fps").textContent = m.playing ? m.fps.toFixed(1) + " (frame " + m.frame_ms.toFixed(1) + " ms)" : "paused";
  if (m.stopped) { $("status").textContent = m.stopped; setPlaying(false); }
  else if ($("status").textContent === "ready" || $("status").textContent.startsWith("playing") || $("status").textContent === "paused")
    $("status").textContent = m.playing ? "playing" : "paused";
  const last = series[series.length - 1];
  if (!last || last.t !== m.time) {
    series.push({ t: m.time, accepted: m.accepted, occupied: m.occupied, surface: m.surface,
      acceptance: m.acceptance, value: m.value, w: m.width_w });
    if (series.length > 20000) series = series.filter((_, i) => i % 2 === 0 || i === series.length - 1);
  }
  drawCharts();
}

function onPick(e) {
  const box = $("explainbox");
  if (e.sampler === "ca") {
    box.innerHTML = "<b>CA update</b>: every surface site with enough occupied neighbours grew at once: " +
      e.grown + " cells. Clock: " + fmt(e.time) + ".";
    lastPick = null; redraw(); return;
  }
  const p = e.pick;
  lastPick = p;
  const vtxt = p.v === 1 ? "v = 1" : "v = " + p.v.toFixed(4) + " (Eq. 5)";
  let html = "<b>Site (" + e.x + ", " + e.y + ")</b>, one of " + p.surface + " surface sites: b = " +
    p.b + " of z = " + p.z + ", " + vtxt + ", n = " + e.n + "<br>p = v (b/z)<sup>n</sup> = " +
    p.p.toPrecision(4) + "<br>";
  if (e.sampler === "rejection") {
    html += "R = " + p.r.toFixed(4) + ": " + (p.accepted ? "<b>R &lt; p: accepted</b>, the site is occupied."
      : "<b>R &ge; p: rejected</b>, nothing changes.") + " The clock advances by one pick: t = " + fmt(e.time) + ".";
  } else {
    html += "<b>Accepted.</b> The exact sampler skipped <b>" + fmt(p.skipped) + "</b> rejected picks: " +
      "each pick is accepted with mean probability P = " + e.mean_p.toPrecision(4) + ", so the number of " +
      "rejections before an acceptance is geometric (mean (1 - P)/P = " + fmt((1 - e.mean_p) / e.mean_p, 2) +
      "). Drawing that number directly and choosing the site in proportion to its p is the same process " +
      "on the same clock: t advanced by " + fmt(p.skipped) + " + 1 to " + fmt(e.time) + ".";
  }
  box.innerHTML = html;
  redraw();
}

function onScenario(text) {
  if (!pendingScenario) return;
  pendingScenario = false;
  download("cellsurf-scenario.toml", new Blob([text], { type: "text/plain" }));
}

// ---------- drawing the lattice ----------
function buildGeometry(hex, w, h, canvas) {
  const physW = hex ? w + 0.5 : w;
  const physH = hex ? (h - 1) * HEX_ROW + 1 : h;
  const maxW = Math.min(960, Math.max(320, window.innerWidth - 420));
  const s = Math.max(1, Math.min(maxW / physW, 620 / physH));
  const cw = Math.ceil(physW * s), ch = Math.ceil(physH * s);
  canvas.width = cw; canvas.height = ch;
  const map = new Int32Array(cw * ch);
  const borders = s >= 7;
  for (let py = 0; py < ch; py++) {
    const y = (ch - 0.5 - py) / s - 0.5;
    for (let px = 0; px < cw; px++) {
      const x = (px + 0.5) / s - 0.5;
      let best = -1, d1 = 1e9, d2 = 1e9;
      if (hex) {
        const r0 = Math.round(y / HEX_ROW);
        for (let r = r0 - 1; r <= r0 + 1; r++) {
          if (r < 0 || r >= h) continue;
          const shift = 0.5 * (r & 1);
          const c0 = Math.round(x - shift);
          for (let c = c0 - 1; c <= c0 + 1; c++) {
            if (c < 0 || c >= w) continue;
            const dx = x - c - shift, dy = y - r * HEX_ROW;
            const d = dx * dx + dy * dy;
            if (d < d1) { d2 = d1; d1 = d; best = r * w + c; } else if (d < d2) d2 = d;
          }
        }
      } else {
        const c = Math.round(x), r = Math.round(y);
        if (c >= 0 && c < w && r >= 0 && r < h) {
          best = r * w + c;
          const fx = 0.5 - Math.abs(x - c), fy = 0.5 - Math.abs(y - r);
          d2 = d1 + 4 * Math.min(fx, fy) * 0.5;  // distance to the edge, for borders
        }
      }
      if (borders && best >= 0 && Math.sqrt(d2) - Math.sqrt(d1) < 1.2 / s) best = -2;
      map[py * cw + px] = best;
    }
  }
  return { hex, w, h, s, cw, ch, map, image: canvas.getContext("2d").createImageData(cw, ch) };
}

function drawFrame(bytes) {
  const kind = bytes[0];
  const dv = new DataView(bytes.buffer, bytes.byteOffset);
  const w = dv.getUint32(2, true), h = dv.getUint32(6, true);
  const states = bytes.subarray(10);
  if (kind === 2) { drawRipple(w, h, states); return; }
  lastFrame = { hex: bytes[1] === 1, w, h, states };
  redraw();
}

function redraw() {
  if (!lastFrame) return;
  const { hex, w, h, states } = lastFrame;
  const canvas = $("canvas");
  if (!geometry || geometry.hex !== hex || geometry.w !== w || geometry.h !== h) geometry = buildGeometry(hex, w, h, canvas);
  const g = geometry, data = g.image.data, map = g.map;
  const pal = [COLORS.empty, COLORS.surface, COLORS.occupied];
  for (let i = 0, j = 0; i < map.length; i++, j += 4) {
    const c = map[i];
    const col = c >= 0 ? pal[states[c]] : (c === -2 ? COLORS.border : COLORS.empty);
    data[j] = col[0]; data[j + 1] = col[1]; data[j + 2] = col[2]; data[j + 3] = 255;
  }
  const ctx = canvas.getContext("2d");
  ctx.putImageData(g.image, 0, 0);
  if (lastPick) {
    const x = lastPick.cell % w, y = Math.floor(lastPick.cell / w);
    const px = hex ? x + 0.5 * (y & 1) : x, py = hex ? y * HEX_ROW : y;
    const cx = (px + 0.5) * g.s, cy = g.ch - (py + 0.5) * g.s;
    ctx.strokeStyle = "#d11"; ctx.lineWidth = 3;
    ctx.beginPath(); ctx.arc(cx, cy, Math.max(6, g.s * 0.9), 0, 2 * Math.PI); ctx.stroke();
  }
}

// ---------- charts ----------
function drawChart(id, lines, opts) {
  const cv = $(id), ctx = cv.getContext("2d");
  const W = cv.width, H = cv.height, L = 46, B = 22, T = 8, R = 8;
  ctx.fillStyle = "#fff"; ctx.fillRect(0, 0, W, H);
  const tx = (v) => (opts.logx ? Math.log10(v) : v), ty = (v) => (opts.logy ? Math.log10(v) : v);
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  for (const ln of lines) for (const [x, y] of ln.pts) {
    if (!(Number.isFinite(x) && Number.isFinite(y)) || (opts.logx && x <= 0) || (opts.logy && y <= 0)) continue;
    x0 = Math.min(x0, tx(x)); x1 = Math.max(x1, tx(x)); y0 = Math.min(y0, ty(y)); y1 = Math.max(y1, ty(y));
  }
  ctx.strokeStyle = "#999"; ctx.strokeRect(L, T, W - L - R, H - T - B);
  if (!Number.isFinite(x0)) return;
  if (x1 === x0) x1 = x0 + 1;
  if (y1 === y0) { y1 = y0 + 1; }
  if (!opts.logy && y0 > 0 && opts.zero) y0 = 0;
  const X = (v) => L + (tx(v) - x0) / (x1 - x0) * (W - L - R);
  const Y = (v) => H - B - (ty(v) - y0) / (y1 - y0) * (H - T - B);
  ctx.fillStyle = "#333"; ctx.font = "10px sans-serif";
  const lab = (v, log) => { const u = log ? Math.pow(10, v) : v; return Math.abs(u) >= 1e4 || (Math.abs(u) < 1e-2 && u !== 0) ? u.toExponential(1) : +u.toPrecision(3); };
  ctx.fillText(lab(y1, opts.logy), 2, T + 8); ctx.fillText(lab(y0, opts.logy), 2, H - B);
  ctx.fillText(lab(x0, opts.logx), L, H - 6); const xl = String(lab(x1, opts.logx));
  ctx.fillText(xl, W - R - ctx.measureText(xl).width, H - 6);
  for (const ln of lines) {
    ctx.strokeStyle = ln.color; ctx.lineWidth = ln.width || 1.5; ctx.setLineDash(ln.dash || []);
    ctx.beginPath(); let started = false;
    for (const [x, y] of ln.pts) {
      if (!(Number.isFinite(x) && Number.isFinite(y)) || (opts.logx && x <= 0) || (opts.logy && y <= 0)) continue;
      if (!started) { ctx.moveTo(X(x), Y(y)); started = true; } else ctx.lineTo(X(x), Y(y));
    }
    ctx.stroke();
  }
  ctx.setLineDash([]);
}

// Least-squares slope of ln y against ln x.
function loglogSlope(pts) {
  const q = pts.filter(([x, y]) => x > 0 && y > 0).map(([x, y]) => [Math.log(x), Math.log(y)]);
  if (q.length < 3) return null;
  const mx = q.reduce((a, p) => a + p[0], 0) / q.length, my = q.reduce((a, p) => a + p[1], 0) / q.length;
  let sxx = 0, sxy = 0;
  for (const [x, y] of q) { sxx += (x - mx) * (x - mx); sxy += (x - mx) * (y - my); }
  return sxx > 0 ? { slope: sxy / sxx, icpt: my - (sxy / sxx) * mx } : null;
}

function drawCharts() {
  const s = series;
  drawChart("chart-counts", [
    { pts: s.map((p) => [p.t, p.occupied]), color: "#222" },
    { pts: s.map((p) => [p.t, p.surface]), color: "#e9a23b" }], { zero: true });
  drawChart("chart-accept", [{ pts: s.map((p) => [p.t, p.acceptance]), color: "#2a6" }], { zero: true });
  drawChart("chart-obs", [{ pts: s.map((p) => [p.t, p.value]), color: "#36c" }], {});
  const wp = s.filter((p) => p.w !== null && p.w !== undefined && p.t > 0).map((p) => [p.t, p.w]);
  const lines = [{ pts: wp, color: "#c33" }];
  let txt = "needs a flat substrate";
  if (wp.length > 5 && info) {
    // Fit over the growth regime: from one monolayer to the end (log t).
    const L = info.width;
    const fitPts = wp.filter(([t]) => t >= 10 * L);
    const fit = loglogSlope(fitPts);
    if (fit) {
      txt = "\u03b2 = " + fit.slope.toFixed(3) + " (KPZ: 1/3), fitted for t \u2265 10 L";
      const ta = fitPts[0][0], tb = fitPts[fitPts.length - 1][0];
      lines.push({ pts: [[ta, Math.exp(fit.icpt) * Math.pow(ta, fit.slope)], [tb, Math.exp(fit.icpt) * Math.pow(tb, fit.slope)]], color: "#555", dash: [4, 3], width: 1 });
      const wb = Math.exp(fit.icpt) * Math.pow(tb, fit.slope);
      lines.push({ pts: [[ta, wb * Math.pow(ta / tb, 1 / 3)], [tb, wb]], color: "#36c", dash: [2, 2], width: 1 });
    } else txt = "growing: \u03b2 is fitted once t \u2265 10 L";
  }
  $("beta").textContent = txt;
  drawChart("chart-w", lines, { logx: true, logy: true });
}

// ---------- controls ----------
function setPlaying(p) { playing = p; $("play").textContent = p ? "Pause" : "Play"; }
function togglePlay() { send({ cmd: playing ? "pause" : "play" }); setPlaying(!playing); }

function restart() {
  const q = currentQuery();
  history.replaceState(null, "", "/?" + q.toString());
  $("linktext").value = linkOf();
  setPlaying(false);
  connect(q);
}

function download(name, blob) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob); a.download = name; document.body.appendChild(a); a.click();
  setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
}

function csv() {
  const rows = ["time,accepted,occupied,surface,acceptance," + (info ? info.preset : "") + "_observable,interface_width"];
  for (const p of series) rows.push([p.t, p.accepted, p.occupied, p.surface, p.acceptance,
    p.value === null ? "" : p.value, p.w === null || p.w === undefined ? "" : p.w].join(","));
  return rows.join("\n") + "\n";
}

function wire() {
  $("preset").addEventListener("change", () => {
    // A new preset: its own settings, keeping only the seed.
    const q = new URLSearchParams({ preset: $("preset").value, seed: $("seed").value });
    history.replaceState(null, "", "/?" + q.toString());
    setPlaying(false);
    info = null;
    connect(q);
  });
  for (const k of CONTROLS) {
    if (k === "preset" || k === "n" || k === "speed") continue;
    $(k).addEventListener("change", restart);
  }
  $("nlog").addEventListener("input", () => { const n = nFromSlider(Number($("nlog").value)); $("n").value = n; $("nval").textContent = n; });
  $("nlog").addEventListener("change", restart);
  $("speedlog").addEventListener("input", () => {
    const v = speedFromSlider(Number($("speedlog").value));
    $("speed").value = v; $("speedval").textContent = v;
    send({ cmd: "speed", value: v });
    history.replaceState(null, "", "/?" + currentQuery().toString());
    $("linktext").value = linkOf();
  });
  $("play").addEventListener("click", togglePlay);
  $("step").addEventListener("click", () => { setPlaying(false); lastPick = null; send({ cmd: "step" }); });
  $("explain").addEventListener("click", () => { setPlaying(false); send({ cmd: "explain" }); });
  $("reset").addEventListener("click", () => { setPlaying(false); series = []; lastPick = null; send({ cmd: "reset" }); });
  $("png").addEventListener("click", () => $("canvas").toBlob((b) => download("cellsurf-lattice.png", b)));
  $("toml").addEventListener("click", () => { pendingScenario = true; send({ cmd: "scenario" }); });
  $("csv").addEventListener("click", () => download("cellsurf-series.csv", new Blob([csv()], { type: "text/csv" })));
  $("copylink").addEventListener("click", () => {
    const link = linkOf();
    $("linktext").value = link; $("linktext").select();
    if (navigator.clipboard) navigator.clipboard.writeText(link).catch(() => {});
  });
  $("alpha").addEventListener("click", () => {
    $("alphaout").textContent = "running...";
    fetch("/api/roughness?n=" + encodeURIComponent($("n").value || "0")).then((r) => r.json()).then((j) => {
      if (j.error) { $("alphaout").textContent = j.error; return; }
      $("alphaout").textContent = "\u03b1 = " + (j.alpha === null ? "-" : j.alpha.toFixed(3)) + " (KPZ: 1/2); w_sat: " +
        j.points.map((p) => "L = " + p.width + ": " + p.w_sat.toFixed(2) + " \u00b1 " + p.se.toFixed(2)).join(", ");
    }).catch((e) => { $("alphaout").textContent = String(e); });
  });
  document.addEventListener("keydown", (ev) => {
    if (ev.target && (ev.target.tagName === "INPUT" || ev.target.tagName === "SELECT")) return;
    if (ev.key === " ") { ev.preventDefault(); togglePlay(); }
    else if (ev.key === "s" || ev.key === "ArrowRight") { setPlaying(false); send({ cmd: "step" }); }
    else if (ev.key === "e") { setPlaying(false); send({ cmd: "explain" }); }
    else if (ev.key === "r") { setPlaying(false); series = []; send({ cmd: "reset" }); }
  });
  window.addEventListener("resize", () => { geometry = null; redraw(); });
}

// ---------- ripples ----------
let rws = null, rplaying = false;
function rippleQuery() {
  return "current_speed=" + $("rspeed").value + "&current_angle=" + $("rangle").value;
}
function rippleConnect(then) {
  if (rws) { rws.onclose = null; rws.close(); }
  rws = new WebSocket((location.protocol === "https:" ? "wss:" : "ws:") + "//" + location.host + "/ws/ripple?" + rippleQuery());
  rws.binaryType = "arraybuffer";
  rws.onmessage = (ev) => {
    if (typeof ev.data !== "string") { drawFrame(new Uint8Array(ev.data)); return; }
    const m = JSON.parse(ev.data);
    if (m.type === "stats") { $("rsteps").textContent = m.time; $("rexposed").textContent = m.exposed; $("rrelief").textContent = m.relief; }
  };
  rws.onopen = () => { if (then) then(); };
  rws.onclose = () => { rplaying = false; $("rplay").textContent = "Play ripples"; };
}
function drawRipple(nx, rows, st) {
  const cv = $("ripplecanvas");
  const px = Math.max(1, Math.floor(960 / nx)), py = 5;
  cv.width = nx * px; cv.height = rows * py;
  const ctx = cv.getContext("2d"), img = ctx.createImageData(cv.width, cv.height), d = img.data;
  for (let Y = 0; Y < cv.height; Y++) {
    const row = rows - 1 - Math.floor(Y / py);
    for (let X = 0; X < cv.width; X++) {
      const s = st[row * nx + Math.floor(X / px)], j = 4 * (Y * cv.width + X);
      let c;
      if (s === 255) c = [160, 120, 60];
      else if (s === 250) c = [220, 30, 30];
      else { const v = (s - 1) / 200; c = [20 + 150 * v, 40 + 170 * v, 120 + 135 * v]; }
      d[j] = c[0]; d[j + 1] = c[1]; d[j + 2] = c[2]; d[j + 3] = 255;
    }
  }
  ctx.putImageData(img, 0, 0);
}
function wireRipple() {
  $("rplay").addEventListener("click", () => {
    const go = () => { rws.send(JSON.stringify({ cmd: rplaying ? "pause" : "play" })); rplaying = !rplaying; $("rplay").textContent = rplaying ? "Pause ripples" : "Play ripples"; };
    if (!rws || rws.readyState > 1) rippleConnect(go); else go();
  });
  $("rreset").addEventListener("click", () => { if (rws && rws.readyState === 1) rws.send(JSON.stringify({ cmd: "reset" })); });
  const cur = () => { $("rspeedval").textContent = $("rspeed").value; if (rws && rws.readyState === 1) rws.send(JSON.stringify({ cmd: "current", speed: Number($("rspeed").value), angle: Number($("rangle").value) })); };
  $("rspeed").addEventListener("input", cur);
  $("rangle").addEventListener("change", cur);
}

// ---------- start ----------
fetch("/api/presets").then((r) => r.json()).then((list) => {
  presets = list;
  for (const p of list) {
    const o = document.createElement("option");
    o.value = p.name; o.textContent = p.name + ": " + p.title;
    $("preset").appendChild(o);
  }
  wire();
  wireRipple();
  const q = queryParams();
  if (q.preset) $("preset").value = q.preset;
  const pass = new URLSearchParams(location.search);
  pass.delete("autoplay"); pass.delete("explain"); pass.delete("tab");
  connect(pass);
  if (q.tab === "ripple") rippleConnect(() => $("rplay").click());
});
