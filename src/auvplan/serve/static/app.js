// auvplan serve: the page. Data only goes to the server (JSON); every check is the server's `mission check`.
"use strict";
const gd = document.getElementById("chart");   // the editable overlay: the mission, its violations, the areas
const bg = document.getElementById("base");    // the report's chart underneath (drawn once per scenario)
const $ = (id) => document.getElementById(id);
let S = null;          // the last state from the server
const C = { rev: null, w: [], v: [] };  // the server's waypoints `w` and violations `v` at revision `rev`
                       // (kept by the answers' splices, delta.js; `rev` goes with every request)
let queue = Promise.resolve();  // the requests, one at a time, each sent on the answer before it
let W = [];            // the waypoints being drawn (copied from C.w)
const MAXDRAWN = 200;  // markers (and labels) drawn per trace at most: plotly thins those in view beyond
const MAXLISTED = 200; // violations listed in the panel at most
const shown = {};      // what each overlay trace and panel shows (skip redrawing what did not change)
let base = 0;          // index of the first trace the page adds to the chart
let mode = "move";
let drag = null;
let drawing = [];
let selected = null;
let generation = -1;
let pending = 0;

const T = { route: 0, bad: 1, area: 2, drawing: 3, flight: 4, marks: 5, keys: 6, nav: 7 };

function fmt(v, d = 1, unit = "") { return v === null || v === undefined ? "—" : `${Number(v).toFixed(d)}${unit}`; }
function hours(s) { return s === null || s === undefined ? "—" : `${(s / 3600).toFixed(2)} h`; }

// Requests go one at a time, each with the revision the answer before it left; an edit carries instead the
// revision of the picture its waypoint was picked on (`rev` in `data`, taken when the user acted), and the
// server refuses it if the mission changed since (HTTP 409): an index never lands on another waypoint.
function call(url, data) {
  pending += 1; $("busy").hidden = false; document.body.dataset.pending = String(pending);
  const p = queue.then(() => send(url, data)).finally(() => {
    pending -= 1; $("busy").hidden = pending === 0;
    document.body.dataset.pending = String(pending);
  });
  queue = p.catch(() => null);
  return p;
}
async function send(url, data) {
  const r = await fetch(url, data === undefined ? {} : {
    method: "POST", headers: { "Content-Type": "application/json" },
    body: JSON.stringify(C.rev === null || "rev" in data ? data : Object.assign({ rev: C.rev }, data)) });
  const j = await r.json();
  if (!r.ok) {
    if (j.stale) { C.rev = null; await send("/api/state"); }  // not applied: show the mission as it is now
    $("error").textContent = j.error || `HTTP ${r.status}`; document.body.dataset.error = j.error || "";
    return null;
  }
  $("error").textContent = ""; document.body.dataset.error = "";
  await show(j);
  return j;
}

function axes() {
  const fl = gd._fullLayout; return [fl.xaxis, fl.yaxis, gd.getBoundingClientRect()];
}
function toData(ev) {
  const [xa, ya, r] = axes();
  return [xa.p2l(ev.clientX - r.left - xa._offset), ya.p2l(ev.clientY - r.top - ya._offset)];
}
function toPx(x, y) {  // page pixels of a local point (also used by the browser tests)
  const [xa, ya, r] = axes();
  return [r.left + xa._offset + xa.l2p(x), r.top + ya._offset + ya.l2p(y)];
}
function inPlot(ev) {
  const [xa, ya, r] = axes(); const px = ev.clientX - r.left - xa._offset, py = ev.clientY - r.top - ya._offset;
  return px >= 0 && px <= xa._length && py >= 0 && py <= ya._length;
}
function nearest(ev, tol) {
  let best = -1, bd = tol * tol;
  W.forEach((p, i) => { const [px, py] = toPx(p[0], p[1]); const d = (px - ev.clientX) ** 2 + (py - ev.clientY) ** 2;
    if (d <= bd) { bd = d; best = i; } });
  return best;
}

function routeTrace() {
  const n = W.length;
  return { x: W.map((p) => p[0]), y: W.map((p) => p[1]), customdata: W.map((p, i) => [i, -p[2]]),
    marker: { size: W.map((_, i) => (i === 0 || i === n - 1 ? 12 : i === selected ? 11 : 7)),
      color: W.map((_, i) => (i === 0 ? "limegreen" : i === n - 1 ? "black" : i === selected ? "deepskyblue" : "orange")),
      line: { width: 1, color: "white" } } };
}
let frame = 0;
function drawRoute() {  // while dragging: at most once per frame
  if (frame) return;
  frame = requestAnimationFrame(() => {
    frame = 0;
    Plotly.restyle(gd, { x: [W.map((p) => p[0])], y: [W.map((p) => p[1])] }, [base + T.route]);
  });
}
// a label as plotly draws it: literally (plotly reads <b>, <br>, <a href> and entities in its texts; a zone named
// "<b>x</b>" was drawn as markup): auvplan.viz.style.plotly_text's escape, in the page
function plotlyText(s) { return String(s).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;"); }
function badTraces() {
  const v = (S && S.check) ? S.check.violations : [];
  const byLeg = new Map();
  v.forEach((e) => { if (!byLeg.has(e.leg)) byLeg.set(e.leg, []); byLeg.get(e.leg).push(e.text); });
  const xs = [], ys = [], mx = [], my = [], txt = [], legs = [];
  byLeg.forEach((texts, leg) => {
    const a = W[leg], b = W[Math.min(leg + 1, W.length - 1)];
    if (!a || !b) return;
    xs.push(a[0], b[0], null); ys.push(a[1], b[1], null);
    mx.push((a[0] + b[0]) / 2); my.push((a[1] + b[1]) / 2); txt.push(texts.map(plotlyText).join("<br>")); legs.push(leg);
  });
  return { xs, ys, mx, my, txt, legs };
}

async function newChart() {
  const r = await fetch("/api/chart"); const fig = await r.json();
  if (!r.ok) { $("error").textContent = fig.error; return; }
  base = 0;  // the overlay holds only the page's traces
  for (const k of Object.keys(shown)) delete shown[k];
  const extra = [
    { type: "scatter", mode: "lines+markers", name: "mission (drag the waypoints)", line: { color: "orange", width: 2.5 },
      marker: { maxdisplayed: MAXDRAWN },
      hovertemplate: "waypoint %{customdata[0]}<br>depth %{customdata[1]:.1f} m<extra></extra>", x: [], y: [] },
    { type: "scatter", mode: "lines", name: "violations", line: { color: "red", width: 6 }, opacity: 0.8,
      hoverinfo: "skip", x: [], y: [] },
    { type: "scatter", mode: "lines", name: "survey area", fill: "toself", fillcolor: "rgba(0,150,255,0.12)",
      line: { color: "dodgerblue", width: 2, dash: "dash" }, hoverinfo: "skip", x: [], y: [] },
    { type: "scatter", mode: "lines+markers", name: "drawing", line: { color: "dodgerblue" }, x: [], y: [] },
    { type: "scatter", mode: "lines", name: "flown track", line: { color: "rgba(30,30,30,0.7)", width: 1.5 },
      hoverinfo: "skip", x: [], y: [] },
    { type: "scatter", mode: "markers+text", name: "violation at leg", marker: { symbol: "x", size: 13, color: "red", maxdisplayed: MAXDRAWN },
      textposition: "top center", textfont: { color: "red", size: 12 }, x: [], y: [],
      hovertemplate: "%{customdata}<extra></extra>" },
    { type: "scatter", mode: "markers", name: "key waypoints", hoverinfo: "skip", x: [], y: [],
      marker: { color: "gold", symbol: "diamond", size: 9, line: { width: 1 } } },
    { type: "scatter", mode: "lines", name: "navigation error band", fill: "toself", fillcolor: "rgba(177,89,40,0.22)",
      line: { color: "#b15928", width: 1 }, hoverinfo: "skip", x: [], y: [] },  // [navigation]: confidence x sigma
  ];
  await Plotly.newPlot(bg, fig.data, Object.assign({}, fig.layout, { dragmode: false }),
    { displaylogo: false, staticPlot: true });
  await Plotly.newPlot(gd, extra, overlayLayout(), { displaylogo: false, doubleClick: false, scrollZoom: true,
    displayModeBar: false });
  gd.on("plotly_relayout", syncBase);
}

// The overlay's plot area and ranges are the chart's, so that an edit redraws the overlay only.
function overlayLayout() {
  const fl = bg._fullLayout, xa = fl.xaxis, ya = fl.yaxis;
  const axis = (a) => ({ range: a.range.slice(), visible: false, showgrid: false, zeroline: false });
  return { width: fl.width, height: fl.height, showlegend: false, hovermode: "closest",
    dragmode: mode === "pan" ? "pan" : false, paper_bgcolor: "rgba(0,0,0,0)", plot_bgcolor: "rgba(0,0,0,0)",
    margin: { l: xa._offset, t: ya._offset, r: fl.width - xa._offset - xa._length,
      b: fl.height - ya._offset - ya._length, pad: 0, autoexpand: false },
    xaxis: axis(xa), yaxis: axis(ya) };
}
let syncing = false;
async function syncBase(ev) {  // pan/zoom on the overlay moves the chart, then the overlay takes the chart's frame
  if (syncing || !ev || !(("xaxis.range[0]" in ev) || ("xaxis.range" in ev) || ("xaxis.autorange" in ev))) return;
  syncing = true;
  try {
    const xa = gd._fullLayout.xaxis, ya = gd._fullLayout.yaxis;
    await Plotly.relayout(bg, { "xaxis.range": xa.range.slice(), "yaxis.range": ya.range.slice() });
    const o = overlayLayout();
    await Plotly.relayout(gd, { margin: o.margin, "xaxis.range": o.xaxis.range, "yaxis.range": o.yaxis.range });
  } finally { syncing = false; }
}

function changed(key, value) {  // true (and remembered) when `value` differs from what `key` last showed
  const v = typeof value === "string" ? value : JSON.stringify(value);
  if (shown[key] === v) return false;
  shown[key] = v; return true;
}

async function show(st) {
  if (C.rev !== null && st.rev !== undefined && st.rev < C.rev) return;  // older than what the page shows
  if (st.generation !== generation) { generation = st.generation; await newChart(); }
  const took = takeState(C, st);  // the whole list, or the splice from the revision the page holds
  if (took === "stale") return;
  if (took === "gap") { await send("/api/state"); return; }  // a splice on another revision: everything
  delete st.waypoints; delete st.delta;
  S = Object.assign(S || {}, st);
  W = C.w.map((p) => p.slice());
  if (S.check) S.check.violations = C.v;
  if (selected !== null && selected >= W.length) selected = null;
  const c = S.check && S.check.summary;
  if (c) {
    $("verdict").textContent = c.ok ? "OK" : "FAIL";
    $("verdict").className = "verdict " + (c.ok ? "ok" : "fail");
    document.body.dataset.ok = String(c.ok);
    const exec = c.executor_min_altitude_m !== null && c.semantics === "held"
      ? `; held-depth executor ${fmt(c.executor_min_altitude_m, 2, " m")}` : "";
    $("min-alt").textContent = c.min_altitude_leg === null ? `no seabed: not checked (required ${fmt(c.required_altitude_m, 0, " m")})`
      : `${fmt(c.min_altitude_m, 2, " m")} (leg ${c.min_altitude_leg}; required ${fmt(c.required_altitude_m, 0, " m")})${exec}`;
    $("min-alt").dataset.value = c.min_altitude_m;
    $("turn").textContent = c.tightest_turn_m === null ? "none (straight)" : `${fmt(c.tightest_turn_m, 1, " m")} (leg ${c.tightest_turn_leg})`;
    $("pitch").textContent = `${fmt(c.max_pitch_deg, 1, "°")} (leg ${c.max_pitch_leg})`;
    $("length").textContent = `${fmt(c.length_m / 1000, 2, " km")}, ${c.waypoints} waypoints`;
    $("duration").textContent = hours(c.duration_s);
    $("energy").textContent = `${fmt(c.energy_wh, 1, " Wh")} (${c.energy_status})`;
    $("energy").dataset.value = c.energy_wh;
    $("margin").textContent = fmt(c.margin_wh, 1, " Wh");
    const nb = S.nav_band;
    $("nav-error").textContent = nb ? `${fmt(nb.max_error_m, 1, " m")} at ${nb.confidence} σ (budget ${nb.budget_m} m, ${nb.fixes} surface fixes)` : "—";
    $("nav-error").dataset.value = nb ? nb.max_error_m : "";
    const ul = $("violations");
    if (changed("violations-list", S.check.violations)) {
      ul.replaceChildren();
      S.check.violations.slice(0, MAXLISTED).forEach((v) => { const li = document.createElement("li"); li.textContent = v.text;
        li.dataset.leg = v.leg; li.dataset.kind = v.kind; if (v.value !== null) li.dataset.value = v.value; ul.appendChild(li); });
      const more = S.check.violations.length - MAXLISTED;
      if (more > 0) { const li = document.createElement("li"); li.className = "more"; li.textContent = `… and ${more} more`; ul.appendChild(li); }
    }
  }
  $("scenario-name").textContent = S.scenario ? `${S.scenario} — ${S.source}` : "";
  if (st.vehicle) {
    document.querySelectorAll("#settings input").forEach((el) => {
      const v = (S[el.dataset.table] || {})[el.dataset.key]; el.value = v === null || v === undefined ? "" : v; });
    $("planner").placeholder = S.planner || "";
    $("semantics").value = S.settings.semantics; $("check-pitch").value = S.settings.pitch_deg;
    const dl = $("builtins"); dl.replaceChildren();
    (S.builtins || []).forEach((n) => { const o = document.createElement("option"); o.value = n; dl.appendChild(o); });
  }
  const tb = document.querySelector("#candidates tbody");
  if (changed("candidates", S.candidates || [])) tb.replaceChildren();
  if (!tb.children.length) (S.candidates || []).forEach((c2, i) => {
    const tr = document.createElement("tr");
    const b = document.createElement("button"); b.textContent = "use"; b.onclick = () => call("/api/choose", { index: i });
    const td0 = document.createElement("td"); td0.appendChild(b); tr.appendChild(td0);
    [c2.name, c2.waypoints, fmt(c2.length_m / 1000, 2), fmt(c2.duration_s / 3600, 2), fmt(c2.energy_wh, 1),
      fmt(c2.margin_wh, 1), fmt(c2.min_altitude_m, 1), fmt(c2.tightest_turn_m, 1), fmt(c2.max_pitch_deg, 1),
      c2.ok ? "OK" : "FAIL"].forEach((v) => { const td = document.createElement("td"); td.textContent = v; tr.appendChild(td); });
    tb.appendChild(tr);
  });
  const ol = $("history");
  if (changed("history", S.history || [])) ol.replaceChildren();
  if (!ol.children.length) (S.history || []).forEach((h) => { const li = document.createElement("li"); li.textContent = h.text; ol.appendChild(li); });
  $("flight").textContent = S.flight ? `flown: ${S.flight.status}, ${fmt(S.flight.metrics.duration_s / 3600, 2)} h, least altitude ${fmt(S.flight.metrics.min_altitude_m, 1, " m")}` : "";
  if (st.result && st.result.saved) $("saved").textContent = `saved in ${st.result.saved}`;
  showSelected();
  redraw();
}

// Redraw the overlay traces whose data changed, in one restyle (one pass of plotly over the chart).
function redraw() {
  if (!gd.data) return;
  const b = badTraces();
  const area = S.survey_area || [];
  const fl = S.flight || { x: [], y: [] };
  const keys = S.keys || [];
  const nb = S.nav_band || { x: [], y: [] };
  const u = undefined;  // restyle leaves an attribute of a trace alone where its value is undefined
  const upd = { x: [], y: [], customdata: [], text: [], "marker.size": [], "marker.color": [] };
  const idx = [];
  const add = (trace, at) => {
    for (const k of Object.keys(upd)) upd[k].push(at[k]);
    idx.push(base + trace);
  };
  if (changed("route", [W, selected])) {
    const r = routeTrace();
    add(T.route, { x: r.x, y: r.y, customdata: r.customdata, "marker.size": r.marker.size,
      "marker.color": r.marker.color });
  }
  if (changed("bad", [b.xs, b.ys])) add(T.bad, { x: b.xs, y: b.ys });
  if (changed("area", area)) add(T.area, { x: area.map((p) => p[0]), y: area.map((p) => p[1]) });
  if (changed("drawing", drawing)) add(T.drawing, { x: drawing.map((p) => p[0]), y: drawing.map((p) => p[1]) });
  if (changed("flight", [fl.x.length, fl.x[0], fl.y[0], fl.x[fl.x.length - 1], fl.y[fl.y.length - 1]])) add(T.flight, { x: fl.x, y: fl.y });
  if (changed("marks", [b.mx, b.my, b.txt])) {
    add(T.marks, { x: b.mx, y: b.my, customdata: b.txt, text: b.legs.map((l) => `leg ${l}`) });
  }
  if (changed("keys", keys)) add(T.keys, { x: keys.map((p) => p[0]), y: keys.map((p) => p[1]) });
  if (changed("nav", [nb.x.length, nb.max_error_m, nb.x[0], nb.y[0], nb.x[nb.x.length - 2]])) add(T.nav, { x: nb.x, y: nb.y });
  if (idx.length) {
    for (const k of Object.keys(upd)) if (upd[k].every((v) => v === u)) delete upd[k];
    Plotly.restyle(gd, upd, idx);
  }
  document.body.dataset.drawn = String(performance.now());
}

function showSelected() {
  if (selected === null || !W[selected]) { $("selected").textContent = "click a waypoint"; return; }
  const p = W[selected];
  $("selected").textContent = `waypoint ${selected}: x ${p[0].toFixed(0)} m, y ${p[1].toFixed(0)} m, depth ${(-p[2]).toFixed(1)} m`;
  $("wp-depth").value = (-p[2]).toFixed(1);
}

function setMode(m) {
  mode = m;
  document.querySelectorAll("button.mode").forEach((b) => b.classList.toggle("on", b.dataset.mode === m));
  Plotly.relayout(gd, { dragmode: m === "pan" ? "pan" : false });
  $("finish-area").disabled = m !== "draw";
  if (m !== "draw") { drawing = []; redraw(); }
}

gd.addEventListener("mousedown", (ev) => {
  if (mode !== "move" || !gd._fullLayout || !inPlot(ev)) return;
  const i = nearest(ev, 12);
  if (i < 0) return;
  drag = { i, moved: false, rev: C.rev }; selected = i; showSelected();
  ev.preventDefault(); ev.stopPropagation();
}, true);
window.addEventListener("mousemove", (ev) => {
  if (!drag) return;
  const [x, y] = toData(ev); W[drag.i][0] = x; W[drag.i][1] = y; drag.moved = true; drawRoute();
});
window.addEventListener("mouseup", async (ev) => {
  if (!drag) return;
  const d = drag; drag = null;
  if (!d.moved) { redraw(); return; }
  const [x, y] = toData(ev);
  await call("/api/edit", { op: "move", index: d.i, x, y, rev: d.rev });
});
gd.addEventListener("click", async (ev) => {
  if (!gd._fullLayout || !inPlot(ev)) return;
  const [x, y] = toData(ev);
  if (mode === "add") await call("/api/edit", { op: "insert", x, y, rev: C.rev });
  else if (mode === "delete") { const i = nearest(ev, 12); if (i >= 0) await call("/api/edit", { op: "delete", index: i, rev: C.rev }); }
  else if (mode === "draw") { drawing.push([x, y]); redraw(); }
}, true);

document.querySelectorAll("button.mode").forEach((b) => { b.onclick = () => setMode(b.dataset.mode); });
$("finish-area").onclick = async () => {
  if (drawing.length < 3) { $("error").textContent = "draw at least 3 corners"; return; }
  const poly = drawing.slice(); drawing = [];
  const r = await call("/api/survey", { polygon: poly });
  if (r) setMode("move");
};
$("undo").onclick = () => call("/api/undo", { rev: C.rev });
$("wp-depth").onchange = () => {
  if (selected === null) return;
  const v = parseFloat($("wp-depth").value);
  if (Number.isFinite(v)) call("/api/edit", { op: "depth", index: selected, z: -v, rev: C.rev });
};
document.querySelectorAll("#settings input").forEach((el) => {
  el.onchange = () => {
    const raw = el.value.trim();
    const value = raw === "" ? null : (el.type === "number" ? Number(raw) : raw);
    call("/api/set", { table: el.dataset.table, key: el.dataset.key, value });
  };
});
$("semantics").onchange = $("check-pitch").onchange = () =>
  call("/api/check", { semantics: $("semantics").value, pitch: Number($("check-pitch").value) });
$("open").onclick = () => call("/api/open", { scenario: $("open-name").value.trim() });
$("import-area").onclick = () => call("/api/survey", { file: $("area-file").value.trim() });
$("plan").onclick = () => {
  const seed = $("seed").value.trim();
  call("/api/plan", { planner: $("planner").value.trim() || null, seed: seed === "" ? null : Number(seed) });
};
$("fly").onclick = () => call("/api/fly", {});
// not queued: the plan or flight it stops is the request the queue is waiting on (its answer then says "stopped")
$("stop").onclick = () => fetch("/api/stop", { method: "POST", headers: { "Content-Type": "application/json" },
                                               body: "{}" });
$("keep").onclick = () => call("/api/keep", {});
$("save").onclick = () => call("/api/save", { name: $("save-name").value.trim() });

window.auvplan = { toPx, state: () => S, waypoints: () => W, setMode, call };
call("/api/state").then(() => { document.body.dataset.ready = "1"; });
