// relief studio: the scene is the document. Every gesture edits the scene JSON, which the server
// generates (POST /api/generate); the heightfield comes back as f32 samples for the 2D map and
// the 3D view. Plain JavaScript, no build step: the server ships this file as it is.
import { setup3d, show3d } from "/view3d.js";
import { centreLine, moveControl, nearestOnLine, placeConstraint, pointAt, smoothThrough } from "/bezier.js";
import { distanceToLine, movePresetPoint, presetLines, presetPoints, regionAt, regionCorners } from "/shapes.js";

const $ = (id) => document.getElementById(id);

// ---------------------------------------------------------------------------------------------
// The document, with undo and redo.

const past = { undo: [], redo: [] };
let doc = null;

/** Replaces the document by `next` (a scene object); `record` keeps the old one for undo. */
function setDoc(next, record = true) {
  if (record && doc) {
    past.undo.push(JSON.stringify(doc));
    past.redo.length = 0;
  }
  doc = next;
  $("scene").value = JSON.stringify(doc, null, 1);
  updateButtons();
  keepDraft();
  scheduleGenerate();
}

// A reload restores the document when it differs from the one last saved, loaded or started
// from a template: it is kept in the browser's storage as it changes.
const DRAFT = "relief-studio-draft";
let cleanText = null;
let restored = false;

/** The document as it is now is saved (or a template's): nothing to restore. */
function markClean() {
  cleanText = JSON.stringify(doc);
  keepDraft();
}

function keepDraft() {
  try {
    const text = JSON.stringify(doc);
    if (text === cleanText) localStorage.removeItem(DRAFT);
    else localStorage.setItem(DRAFT, JSON.stringify({ doc: text, name: $("name").value }));
  } catch (_) {
    // Storage full (a scene of megabytes) or disabled: no draft, rather than an older one.
    try {
      localStorage.removeItem(DRAFT);
    } catch (_) {
      // Disabled: there is none.
    }
  }
}

/** The unsaved document a reload left, if any. */
function readDraft() {
  try {
    const draft = JSON.parse(localStorage.getItem(DRAFT));
    return draft && typeof draft.doc === "string" ? draft : null;
  } catch (_) {
    return null;
  }
}

// The document a map gesture made (undone if the server refuses it), and the text of the
// document whose result is shown.
let gestureDoc = null;
let shownDoc = null;
// The map shows an uploaded DEM opened as it is (Open DEM), not the scene's result: gestures
// are refused until the scene is generated again.
let viewingUpload = false;

/** Applies `edit` to a copy of the document and records it. */
function editDoc(edit) {
  const next = JSON.parse(JSON.stringify(doc));
  edit(next);
  setDoc(next);
  gestureDoc = next;
}

/** The server refused the document the last gesture made: that gesture is undone (not kept for
 * redo), so the next gestures apply to a document that generates, and the refusal is shown. */
function refuseGesture(text) {
  doc = JSON.parse(past.undo.pop());
  gestureDoc = null;
  $("scene").value = JSON.stringify(doc, null, 1);
  updateButtons();
  $("message").textContent = `that gesture was refused and undone: ${text}`;
  setState("refused", "gesture refused");
  if (JSON.stringify(doc) !== shownDoc) scheduleGenerate();
}

function undo() {
  if (!past.undo.length) return;
  past.redo.push(JSON.stringify(doc));
  setDoc(JSON.parse(past.undo.pop()), false);
}

function redo() {
  if (!past.redo.length) return;
  past.undo.push(JSON.stringify(doc));
  setDoc(JSON.parse(past.redo.pop()), false);
}

function updateButtons() {
  $("undo").disabled = !past.undo.length;
  $("redo").disabled = !past.redo.length;
  const kind = generatorKind();
  $("island-tools").classList.toggle("hidden", kind !== "island");
  $("contour-tools").classList.toggle("hidden", kind !== "contours");
  $("diffusion-tools").classList.toggle("hidden", kind !== "diffusion");
  $("gaussian-tools").classList.toggle("hidden", kind !== "gaussian");
  $("orometry-tools").classList.toggle("hidden", kind !== "orometry");
}

/** The generator's name: `island`, `contours`, `diffusion`, `gaussian` or `orometry`. */
function generatorKind() {
  return doc && doc.generator ? Object.keys(doc.generator)[0] : null;
}

// ---------------------------------------------------------------------------------------------
// Generation: a newer edit supersedes a running one.

let result = null; // { id, width, height, min, max, extent, sea_level, z: Float32Array }
let generation = 0;
let inFlight = null;
let timer = null;

function scheduleGenerate() {
  clearTimeout(timer);
  timer = setTimeout(generate, 120);
}

function setState(state, text) {
  document.body.dataset.state = state;
  $("status").textContent = text;
}

// This page's session: its newer generation cancels its older one on the server too.
const session = Array.from(crypto.getRandomValues(new Uint8Array(12)), (b) => b.toString(16).padStart(2, "0")).join("");
// Every request with a body says JSON: the studio refuses other types (another site's form).
const jsonBody = { "content-type": "application/json" };
const headers = { ...jsonBody, "x-relief-session": session };
// End-to-end times of the generations shown: [{ server_ms, total_ms }].
const timings = [];

async function generate() {
  const mine = ++generation;
  if (inFlight) inFlight.abort();
  inFlight = new AbortController();
  const signal = inFlight.signal;
  setState("generating", "generating…");
  const start = performance.now();
  listen();
  const sent = doc;
  try {
    const response = await fetch("/api/generate", { method: "POST", body: JSON.stringify(sent), headers, signal });
    const body = await response.json();
    if (mine !== generation || response.status === 409) return;
    if (!response.ok) {
      const text = (body.path ? body.path + ": " : "") + body.error;
      if (response.status === 422 && sent === gestureDoc && sent === doc && past.undo.length) return refuseGesture(text);
      $("message").textContent = text;
      setState("error", "error " + response.status);
      return;
    }
    const samples = await fetch(`/api/results/${body.id}/elevation`, { signal });
    const z = new Float32Array(await samples.arrayBuffer());
    if (mine !== generation) return;
    shownDoc = JSON.stringify(sent);
    viewingUpload = false;
    showResult(Object.assign(body, { z }));
    const total = performance.now() - start;
    timings.push({ server_ms: body.ms, total_ms: total });
    setState("idle", `${result.width}×${result.height} · server ${body.ms.toFixed(0)} ms · shown in ${total.toFixed(0)} ms`);
  } catch (error) {
    if (error.name !== "AbortError") {
      $("message").textContent = String(error);
      setState("error", "failed");
    }
  } finally {
    if (mine === generation) stopListening();
  }
}

// The session's progress stream (GET /api/events), open while a generation runs.
let events = null;

function listen() {
  if (events) return;
  events = new EventSource(`/api/events?session=${session}`);
  events.addEventListener("progress", (event) => showProgress(JSON.parse(event.data)));
}

function stopListening() {
  if (events) events.close();
  events = null;
}

/** Makes `r` (a result with its samples `z`) the current one and draws it. */
function showResult(r) {
  result = r;
  $("message").textContent = restored ? "restored the unsaved scene this page held before it was reloaded" : "";
  restored = false;
  downloadLinks();
  $("summary").textContent = summaryText(r);
  renderRelief();
  peaks = null;
  drawMap();
  const table = tintTable();
  show3d(result, (v) => {
    const c = 3 * tintIndex(v);
    return [table[c], table[c + 1], table[c + 2]];
  });
  loadPeaks();
  loadSkeleton();
  document.body.dataset.resultId = String(result.id);
}

/** Points the Download link at the result in the chosen format; a RAW16 also gets its sidecar. */
function downloadLinks() {
  const format = $("format").value;
  $("download").href = `/api/results/${result.id}/download/${format}`;
  $("download-sidecar").href = `/api/results/${result.id}/download/r16.json`;
  $("download-sidecar").hidden = format !== "r16";
}

/** Shows the server's step while a generation runs: `state` is an event of the session's
 * progress stream (GET /api/events), sent each time it changes. */
function showProgress(state) {
  if (document.body.dataset.state !== "generating" || !state.running) return;
  const counted = state.total ? ` ${state.done}/${state.total}` : "";
  $("status").textContent = `generating: ${state.step}${counted}…`;
}

/** Stops the running generation, on the server too. */
async function cancel() {
  generation++;
  if (inFlight) inFlight.abort();
  stopListening();
  await fetch("/api/cancel", { method: "POST", headers });
  setState("idle", "cancelled");
}

function summaryText(r) {
  const lines = [`elevation ${r.min.toFixed(1)} … ${r.max.toFixed(1)} m`];
  if (r.sea_level !== null && r.sea_level !== undefined) lines.push(`sea level ${r.sea_level.toFixed(1)} m`);
  for (const t of r.timings || []) lines.push(`${t.step}: ${t.ms.toFixed(0)} ms`);
  for (const w of r.warnings || []) lines.push(`warning: ${w}`);
  return lines.join("\n");
}

// ---------------------------------------------------------------------------------------------
// Colours and shading shared by both views.

function seaLevel() {
  return result.sea_level === null || result.sea_level === undefined ? -Infinity : result.sea_level;
}

/** Hypsometric tint of `z`: blues under the sea, green to brown to white above it. */
function tint(z) {
  const sea = seaLevel();
  if (!(z === z)) return [40, 40, 40];
  if (z < sea) {
    const t = Math.min(1, (sea - z) / Math.max(1, sea - result.min));
    return [40 - 20 * t, 90 - 40 * t, 160 - 50 * t];
  }
  const low = Math.max(sea, result.min);
  const t = Math.max(0, Math.min(1, (z - low) / Math.max(1e-6, result.max - low)));
  const stops = [[0, [86, 140, 80]], [0.35, [170, 170, 100]], [0.7, [140, 100, 70]], [1, [240, 240, 240]]];
  for (let k = 1; k < stops.length; k++) {
    if (t <= stops[k][0]) {
      const [t0, c0] = stops[k - 1];
      const [t1, c1] = stops[k];
      const u = (t - t0) / (t1 - t0);
      return c0.map((c, i) => c + (c1[i] - c) * u);
    }
  }
  return stops[stops.length - 1][1];
}

/** A round contour interval giving about 20 levels. */
function contourInterval() {
  const raw = Math.max(1e-6, (result.max - result.min) / 20);
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  return [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw);
}

// ---------------------------------------------------------------------------------------------
// The 2D map: shaded relief, tint, contours, and the scene's inputs over them.

// World units to canvas pixels: `sx`, `sy` per unit along x and y (equal on planar grids; a
// geographic grid's degrees of longitude are narrower), the origin at (`ox`, `oy`).
const view = { scale: 1, sx: 1, sy: 1, ox: 0, oy: 0 };

function worldToCanvas([x, y]) {
  const e = result.extent;
  return [view.ox + (x - e.min[0]) * view.sx, view.oy + (e.max[1] - y) * view.sy];
}

function canvasToWorld(cx, cy) {
  const e = result.extent;
  return [e.min[0] + (cx - view.ox) / view.sx, e.max[1] - (cy - view.oy) / view.sy];
}

/** The tint of 1024 elevations evenly spread over the result's range, RGB. */
function tintTable() {
  const table = new Uint8ClampedArray(3 * 1024);
  for (let k = 0; k < 1024; k++) {
    table.set(tint(result.min + ((result.max - result.min) * k) / 1023), 3 * k);
  }
  return table;
}

/** The index of `v` in the tint table. */
function tintIndex(v) {
  const t = (v - result.min) / Math.max(1e-9, result.max - result.min);
  return v === v ? Math.max(0, Math.min(1023, Math.round(t * 1023))) : 0;
}

// The shaded relief of the current result, drawn once per result; gestures redraw over it.
let relief = null;

/** Renders the result's shaded relief, tint and contours into `relief`. */
function renderRelief() {
  const { width: w, height: h, z } = result;
  const e = result.extent;
  const [mx, my] = result.metres_per_unit;
  const dx = (mx * (e.max[0] - e.min[0])) / Math.max(1, w - 1);
  const dy = (my * (e.max[1] - e.min[1])) / Math.max(1, h - 1);
  const image = new ImageData(w, h);
  const data = image.data;
  const table = tintTable();
  const interval = contourInterval();
  const band = new Int32Array(w * h);
  for (let k = 0; k < w * h; k++) band[k] = Math.floor((z[k] - result.min) / interval);
  for (let j = 0; j < h; j++) {
    const up = Math.max(0, j - 1) * w;
    const down = Math.min(h - 1, j + 1) * w;
    for (let i = 0; i < w; i++) {
      const k = j * w + i;
      const gx = (z[j * w + Math.min(w - 1, i + 1)] - z[j * w + Math.max(0, i - 1)]) / (2 * dx);
      const gy = (z[up + i] - z[down + i]) / (2 * dy);
      // Light from the north-west, 45° up; darker on contour lines.
      let shade = Math.max(0, (gx * -0.5 + gy * 0.5 + 0.7071) / Math.sqrt(gx * gx + gy * gy + 1)) * 0.75 + 0.35;
      if ((i + 1 < w && band[k + 1] !== band[k]) || (j + 1 < h && band[k + w] !== band[k])) shade *= 0.55;
      const c = 3 * tintIndex(z[k]);
      data[4 * k] = table[c] * shade;
      data[4 * k + 1] = table[c + 1] * shade;
      data[4 * k + 2] = table[c + 2] * shade;
      data[4 * k + 3] = 255;
    }
  }
  relief = new OffscreenCanvas(w, h);
  relief.getContext("2d").putImageData(image, 0, 0);
}

/** Draws the relief and the scene's inputs on the map. */
function drawMap() {
  const canvas = $("map");
  const ctx = canvas.getContext("2d");
  ctx.fillStyle = "#111";
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  if (!result) return;
  const e = result.extent;
  const [mx, my] = result.metres_per_unit;
  const [width, height] = [mx * (e.max[0] - e.min[0]), my * (e.max[1] - e.min[1])];
  const perMetre = Math.min(canvas.width / width, canvas.height / height);
  [view.sx, view.sy, view.scale] = [perMetre * mx, perMetre * my, perMetre * mx];
  view.ox = (canvas.width - width * perMetre) / 2;
  view.oy = (canvas.height - height * perMetre) / 2;
  ctx.imageSmoothingEnabled = true;
  ctx.drawImage(relief, view.ox, view.oy, width * perMetre, height * perMetre);
  drawInputs(ctx);
}

function polyline(ctx, points, close) {
  if (!points || points.length < 2) return;
  ctx.beginPath();
  points.forEach((p, k) => {
    const [x, y] = worldToCanvas(p);
    if (k === 0) ctx.moveTo(x, y);
    else ctx.lineTo(x, y);
  });
  if (close) ctx.closePath();
  ctx.stroke();
}

/** The island's hills after its operations: `{center, radii, height}` in index order. */
function islandHills() {
  const hills = [];
  for (const op of doc.generator.island.operations || []) {
    const [name, v] = Object.entries(op)[0];
    if (name === "add_hill") hills.push({ center: v.center, radii: v.radii, height: v.height });
    else if (name === "move_hill" && hills[v.hill]) hills[v.hill].center = v.center;
    else if (name === "resize_hill" && hills[v.hill]) hills[v.hill].radii = v.radii;
    else if (name === "remove_hill") hills.splice(v.hill, 1);
  }
  return hills;
}

function drawInputs(ctx) {
  ctx.lineWidth = 1.5;
  const kind = generatorKind();
  if (kind === "island") {
    ctx.strokeStyle = "rgba(255, 230, 120, 0.9)";
    for (const op of doc.generator.island.operations || []) {
      const [name, v] = Object.entries(op)[0];
      if (name === "stroke" || name === "coastline") polyline(ctx, v.points, name === "coastline");
    }
    islandHills().forEach((hill, k) => {
      const [x, y] = worldToCanvas(hill.center);
      ctx.strokeStyle = hill.height < 0 ? "rgba(120, 200, 255, 0.9)" : "rgba(255, 255, 255, 0.9)";
      ctx.beginPath();
      ctx.ellipse(x, y, hill.radii[0] * view.sx, hill.radii[1] * view.sy, 0, 0, 2 * Math.PI);
      ctx.stroke();
      ctx.fillStyle = "#fff";
      ctx.fillText(String(k), x + 3, y - 3);
    });
  } else if (kind === "contours") {
    for (const region of doc.generator.contours.regions || []) {
      ctx.strokeStyle = region.depression ? "rgba(120, 200, 255, 0.9)" : "rgba(255, 255, 255, 0.8)";
      ctx.setLineDash(region.depression ? [4, 3] : []);
      polyline(ctx, region.polygon.exterior, true);
    }
    ctx.setLineDash([]);
    if (tool() === "move-corner") drawHandles(ctx, regionCorners(doc.generator.contours.regions));
    ctx.strokeStyle = "rgba(255, 150, 80, 0.9)";
    for (const edit of doc.edits || []) {
      if (edit.warp) polyline(ctx, edit.warp.stroke, false);
    }
  }
  if (kind === "diffusion") {
    const g = doc.generator.diffusion;
    ctx.strokeStyle = "rgba(255, 90, 90, 0.9)";
    for (const preset of g.presets || []) {
      const v = Object.values(preset)[0];
      if (v.points) polyline(ctx, v.points, false);
      if (v.ends) v.ends.forEach((end) => polyline(ctx, [v.peak, end], false));
    }
    for (const curve of g.curves || []) polyline(ctx, centreLine(curve.points), false);
    if (tool() === "move-control" || tool() === "constrain") drawCurveHandles(ctx, g.curves || []);
    if (tool() === "move-feature") drawHandles(ctx, presetPoints(g.presets));
  }
  if (kind === "orometry" && result.divide_tree) drawTree(ctx, result.divide_tree);
  if (kind === "gaussian" && skeleton && tool() === "move-crest") drawSkeleton(ctx);
  if (peaks && $("show-peaks").checked) drawPeaks(ctx);
  if (paint.canvas && tool() === "paint" && sameExtent(paint.extent, result.extent)) {
    const [x0, y0] = worldToCanvas([paint.extent.min[0], paint.extent.max[1]]);
    const [x1, y1] = worldToCanvas([paint.extent.max[0], paint.extent.min[1]]);
    ctx.globalAlpha = 0.3;
    ctx.drawImage(paint.canvas, x0, y0, x1 - x0, y1 - y0);
    ctx.globalAlpha = 1;
  }
  if (pending.points.length) {
    ctx.strokeStyle = "#ff0";
    polyline(ctx, pending.points, false);
  }
}

// The result's peaks and divide tree (GET /api/results/{id}/peaks), drawn when asked for.
let peaks = null;

async function loadPeaks() {
  if (!result || !$("show-peaks").checked) return;
  const id = result.id;
  const min = $("min-prominence").value;
  const query = min === "" ? "" : `?min_prominence=${Number(min)}`;
  const response = await fetch(`/api/results/${id}/peaks${query}`);
  const body = await response.json();
  if (!result || result.id !== id) return;
  if (!response.ok) {
    $("message").textContent = body.error;
    return;
  }
  peaks = body;
  document.body.dataset.peaks = String(peaks.peaks.length);
  drawMap();
}

/** An orometry scene's generated divide tree: each saddle joined to its two peaks, peaks numbered. */
function drawTree(ctx, tree) {
  ctx.strokeStyle = "rgba(255, 200, 60, 0.9)";
  for (const saddle of tree.saddles) {
    polyline(ctx, [tree.peaks[saddle.peaks[0]].position, saddle.position, tree.peaks[saddle.peaks[1]].position], false);
  }
  ctx.fillStyle = "rgba(255, 240, 180, 1)";
  for (const saddle of tree.saddles) {
    const [x, y] = worldToCanvas(saddle.position);
    ctx.beginPath();
    ctx.moveTo(x, y - 4);
    ctx.lineTo(x + 4, y);
    ctx.lineTo(x, y + 4);
    ctx.lineTo(x - 4, y);
    ctx.fill();
  }
  ctx.fillStyle = "rgba(255, 200, 60, 1)";
  tree.peaks.forEach((p, k) => {
    const [x, y] = worldToCanvas(p.position);
    ctx.fillRect(x - 2, y - 2, 5, 5);
    ctx.fillText(String(k), x + 4, y - 4);
  });
}

/** The item of `items` whose world position `at(item)` is nearest `p`, within `pixels` on the
 * map: `{ item, index, distance }` (the first of equals), or null. The tools that pick a point
 * (tree peaks and saddles, control points, crest nodes) share this rule. */
function nearest(items, p, pixels, at) {
  let best = null;
  items.forEach((item, index) => {
    const q = at(item);
    const distance = Math.hypot(q[0] - p[0], q[1] - p[1]);
    if (distance * view.scale <= pixels && (!best || distance < best.distance)) best = { item, index, distance };
  });
  return best;
}

/** Pixels within which a press picks a divide-tree peak or saddle. */
const TREE_PICK = 16;

/** The index of the shown divide tree's peak (`"peaks"`) or saddle (`"saddles"`) within
 * [`TREE_PICK`] pixels of `p`, or -1 (also while a newer generation runs: the shown tree is then
 * not the scene's). */
function nearestTreeItem(kind, p) {
  const tree = result && result.divide_tree;
  if (!tree || !treeIsCurrent()) return -1;
  const found = nearest(tree[kind], p, TREE_PICK, (q) => q.position);
  return found ? found.index : -1;
}

/** Whether the shown tree is the scene's: not while a newer generation runs. */
function treeIsCurrent() {
  return document.body.dataset.state !== "generating";
}

// Divide-tree tools beyond the peak ones: a press at `start` released at `end`.
const TREE_TOOLS = {
  // A new peak at the height setting where the drag ends, joined to the peak it starts from by a
  // saddle halfway, below both.
  "insert-peak": (start, end, height) => {
    const from = nearestTreeItem("peaks", start);
    if (from < 0) return refuse("drag from a peak of the generated divide tree (once it is shown, and not while a newer one is generated)");
    const peak = result.divide_tree.peaks[from];
    const low = Math.min(peak.elevation, height);
    const saddle = roundWorld([(peak.position[0] + end[0]) / 2, (peak.position[1] + end[1]) / 2]);
    addTreeEdit({ op: "insert_peak", position: end, elevation: height, connect_to: from, saddle, saddle_elevation: low - 0.3 * Math.abs(low) });
  },
  "move-saddle": (start, end) => {
    const saddle = nearestTreeItem("saddles", start);
    if (saddle < 0) return refuse("drag a saddle of the generated divide tree (the diamonds)");
    addTreeEdit({ op: "move_saddle", saddle, position: end });
  },
  "delete-ridge": (start) => {
    const saddle = nearestTreeItem("saddles", start);
    if (saddle < 0) return refuse("click a saddle of the generated divide tree (the diamonds)");
    addTreeEdit({ op: "delete_ridge", saddle });
  },
};

/** Appends an edit to an orometry scene's tree. */
function addTreeEdit(edit) {
  editDoc((d) => (d.generator.orometry.edits = (d.generator.orometry.edits || []).concat([edit])));
}

function drawPeaks(ctx) {
  ctx.strokeStyle = "rgba(255, 120, 200, 0.9)";
  for (const saddle of peaks.saddles) polyline(ctx, saddle.ridge, false);
  const ranked = peaks.peaks.map((p, k) => [p.prominence, k]).sort((a, b) => b[0] - a[0]);
  const labelled = new Set(ranked.slice(0, 12).map(([, k]) => k));
  ctx.fillStyle = "rgba(255, 120, 200, 1)";
  peaks.peaks.forEach((p, k) => {
    const [x, y] = worldToCanvas(p.position);
    ctx.beginPath();
    ctx.moveTo(x, y - 5);
    ctx.lineTo(x - 4, y + 3);
    ctx.lineTo(x + 4, y + 3);
    ctx.fill();
    if (labelled.has(k)) ctx.fillText(`${p.elevation.toFixed(0)} (${p.prominence.toFixed(0)})`, x + 5, y - 5);
  });
}

// ---------------------------------------------------------------------------------------------
// Tools: each gesture becomes one scene edit.

const pending = { points: [], start: null, hill: -1, control: null, shape: null };

function tool() {
  return document.querySelector('input[name="tool"]:checked').value;
}

function pointerWorld(event) {
  const canvas = $("map");
  const rect = canvas.getBoundingClientRect();
  const cx = ((event.clientX - rect.left) * canvas.width) / rect.width;
  const cy = ((event.clientY - rect.top) * canvas.height) / rect.height;
  return roundWorld(canvasToWorld(cx, cy));
}

/** `p` rounded to a tenth of a pixel's size: short JSON, and no precision lost in degrees. */
function roundWorld(p) {
  const step = Math.pow(10, Math.floor(Math.log10(1 / view.sx)) - 1);
  return p.map((v) => Math.round(v / step) * step).map((v) => Number(v.toPrecision(12)));
}

// The growth-probability painting (a gray image over the result's extent, brighter grows first):
// each stroke is uploaded as a new file and set as the scene's probability map, so undo brings
// the earlier painting back.
const paint = { canvas: null, strokes: 0, extent: null };

function paintAt(p) {
  const e = paint.extent;
  const c = paint.canvas;
  const x = ((p[0] - e.min[0]) / (e.max[0] - e.min[0])) * c.width;
  const y = ((e.max[1] - p[1]) / (e.max[1] - e.min[1])) * c.height;
  const r = (radius() / (e.max[0] - e.min[0])) * c.width;
  const ctx = c.getContext("2d");
  const brush = ctx.createRadialGradient(x, y, 0, x, y, r);
  brush.addColorStop(0, "rgba(255, 255, 255, 0.35)");
  brush.addColorStop(1, "rgba(255, 255, 255, 0)");
  ctx.fillStyle = brush;
  ctx.fillRect(x - r, y - r, 2 * r, 2 * r);
}

function startPainting() {
  if (!paint.canvas || !sameExtent(paint.extent, result.extent)) {
    paint.canvas = new OffscreenCanvas(256, 256);
    const ctx = paint.canvas.getContext("2d");
    ctx.fillStyle = "rgb(128, 128, 128)";
    ctx.fillRect(0, 0, 256, 256);
    paint.extent = result.extent;
  }
}

function sameExtent(a, b) {
  return a && b && a.min[0] === b.min[0] && a.min[1] === b.min[1] && a.max[0] === b.max[0] && a.max[1] === b.max[1];
}

async function finishPainting() {
  const blob = await paint.canvas.convertToBlob({ type: "image/png" });
  const name = `growth-${session}-${++paint.strokes}.png`;
  const response = await fetch(`/api/files/${name}`, { method: "PUT", body: blob });
  if (!response.ok) {
    $("message").textContent = (await response.json()).error;
    return;
  }
  const extent = paint.extent;
  editDoc((d) => (d.generator.contours.probability = { image: { path: name, extent } }));
}

function onPointerDown(event) {
  if (!result) return;
  if (viewingUpload) {
    // The map shows a DEM opened as it is: its coordinates are not the scene's.
    $("message").textContent =
      "the map shows the opened DEM, not the scene: Vectorize, Synthesize or Trace it, or start a scene, to edit";
    return;
  }
  const p = pointerWorld(event);
  const t = tool();
  if (t === "paint") {
    startPainting();
    paintAt(p);
  }
  if (t === "region" || t === "depression") {
    pending.points.push(p);
    drawMap();
    return;
  }
  $("map").setPointerCapture(event.pointerId);
  pending.start = p;
  pending.points = [p];
  if (t === "move-hill" || t === "resize-hill" || t === "remove-hill") {
    const hills = islandHills();
    const near = (h) => Math.hypot(h.center[0] - p[0], h.center[1] - p[1]);
    pending.hill = hills.length ? hills.indexOf(hills.reduce((a, b) => (near(a) <= near(b) ? a : b))) : -1;
  }
  if (t === "move-control") pending.control = nearestControl(p);
  if (t === "move-feature") pending.shape = nearest(presetPoints(doc.generator.diffusion.presets), p, 12, (a) => a.q);
  if (t === "move-corner") pending.shape = nearest(regionCorners(doc.generator.contours.regions), p, 12, (a) => a.q);
}

function onPointerMove(event) {
  if (!pending.start) return;
  const p = pointerWorld(event);
  const last = pending.points[pending.points.length - 1];
  if (Math.hypot(p[0] - last[0], p[1] - last[1]) * view.scale >= 4) {
    if (tool() === "paint") paintAt(p);
    pending.points.push(p);
    drawMap();
  }
}

function onPointerUp(event) {
  if (!pending.start) return;
  const end = pointerWorld(event);
  const start = pending.start;
  const points = pending.points;
  pending.start = null;
  pending.points = [];
  const t = tool();
  const height = Number($("height").value);
  if ((t === "stroke" || t === "coastline") && points.length >= 3) {
    const ring = t === "coastline" ? points.concat([points[0]]) : points;
    editDoc((d) => d.generator.island.operations.push({ [t]: { points: ring } }));
  } else if (t === "hill" || t === "hollow") {
    const r = Math.max(Math.hypot(end[0] - start[0], end[1] - start[1]), 8 / view.scale);
    const h = t === "hollow" ? -Math.abs(height) : Math.abs(height);
    editDoc((d) => d.generator.island.operations.push({ add_hill: { center: start, radii: [r, r], height: h } }));
  } else if (t === "move-hill" && pending.hill >= 0) {
    const hill = pending.hill;
    editDoc((d) => d.generator.island.operations.push({ move_hill: { hill, center: end } }));
  } else if (t === "paint") {
    finishPainting();
  } else if (TREE_TOOLS[t]) {
    TREE_TOOLS[t](start, end, height);
  } else if (t === "move-peak" || t === "peak-height" || t === "delete-peak") {
    const peak = nearestTreeItem("peaks", start);
    if (peak < 0) return refuse("press on a peak of the generated divide tree (once it is shown, and not while a newer one is generated)");
    const position = result.divide_tree.peaks[peak].position;
    if (t === "move-peak") addTreeEdit({ op: "move_peak", peak, position: end });
    else if (t === "peak-height") addTreeEdit({ op: "move_peak", peak, position, elevation: height });
    else addTreeEdit({ op: "delete_peak", peak });
  } else if (t === "resize-hill" && pending.hill >= 0) {
    const hill = pending.hill;
    const c = islandHills()[hill].center;
    const r = Math.max(Math.hypot(end[0] - c[0], end[1] - c[1]), 8 / view.scale);
    editDoc((d) => d.generator.island.operations.push({ resize_hill: { hill, radii: [r, r] } }));
  } else if (t === "remove-hill" && pending.hill >= 0) {
    const hill = pending.hill;
    editDoc((d) => d.generator.island.operations.push({ remove_hill: { hill } }));
  } else if (t === "warp" && points.length >= 2) {
    addEdit({ warp: { stroke: points, radius: radius() } });
  } else if (t === "slope" && points.length >= 3) {
    addEdit({ slope: { curve: simplified(points), radius: radius(), strength: 1.0 } });
  } else if (CONTOUR_CLICKS[t]) {
    addEdit(CONTOUR_CLICKS[t](start));
  } else if ((t === "cut" || t === "paste") && points.length >= 2) {
    // The relief inside the contour around the press of the height setting, as Delete picks it.
    addEdit({ [t]: { at: start, height: Number($("height").value), to: end } });
  } else if (CURVE_TOOLS[t]) {
    CURVE_TOOLS[t](start, end, points);
  } else if (SHAPE_TOOLS[t]) {
    SHAPE_TOOLS[t](start, end);
  } else if (PRESETS[t] && points.length >= 3) {
    const preset = PRESETS[t](simplified(points), Math.abs(Number($("height").value)));
    editDoc((d) => (d.generator.diffusion.presets = (d.generator.diffusion.presets || []).concat([preset])));
  } else if (GAUSSIAN_TOOLS[t]) {
    const tool = GAUSSIAN_TOOLS[t](start, end, points.length);
    if (tool) editDoc((d) => d.generator.gaussian.operations.push(tool));
    else drawMap();
  } else {
    drawMap();
  }
}

/** The radius setting, world units. */
function radius() {
  return Math.abs(Number($("warp-radius").value)) || 1;
}

/** Appends a contour edit. */
function addEdit(edit) {
  editDoc((d) => (d.edits = (d.edits || []).concat([edit])));
}

// Contour tools that take one click: the edit at the point.
const CONTOUR_CLICKS = {
  smooth: (p) => ({ smooth: { centre: p, radius: radius(), alpha: 0.6, iterations: 4 } }),
  slope: (p) => ({ slope: { point: p, radius: radius(), strength: 1.0 } }),
  delete: (p) => ({ delete: { at: p, height: Number($("height").value) } }),
  fill: (p) => ({ fill: { at: p, height: Number($("height").value) } }),
};

// Feature-curve presets from a dragged course and the height setting.
const PRESETS = {
  ridge: (points, h) => ({ ridge: { points, start_h: 0.3 * h, peak_h: h, end_h: 0.3 * h, angle: 30, extent: radius() } }),
  riverbed: (points, h) => ({ riverbed: { points, start_h: 0.2 * h, end_h: 0.1 * h, width: radius() / 8, bank_angle: 8, bank: radius() } }),
  cliff: (points, h) => ({ cliff: { points, h, drop_angle: 60, extent: radius() / 2 } }),
  "hill-curve": (points, h) => ({ hill: { points, h, extent: radius() } }),
  crack: (points) => ({ crack: { points, angle: 40, extent: radius() / 2 } }),
};

// Free feature curves (§3.1): drawn as smooth Béziers, constrained at any point, reshaped by
// their control points. Constraints take the settings: the height, the slope angles over the
// radius, the noise.
const CURVE_TOOLS = {
  bezier: (start, end, points) => {
    const anchors = simplified(points);
    const step = Math.ceil((anchors.length - 1) / 7);
    const kept = anchors.filter((_, k) => k % step === 0 || k === anchors.length - 1);
    const constraints = [curveConstraint(0), curveConstraint(1)];
    if (kept.length < 2 || !hasConstraint(constraints[0])) return refuse("draw a longer curve, with at least one constraint group ticked");
    const curve = { points: smoothThrough(kept, roundWorld), constraints };
    editDoc((d) => (d.generator.diffusion.curves = (d.generator.diffusion.curves || []).concat([curve])));
  },
  constrain: (start) => {
    const near = nearestCurve(start);
    const added = near && curveConstraint(near.u);
    if (!near || !hasConstraint(added)) return refuse("click on a Bézier curve, with at least one constraint group ticked");
    editDoc((d) => {
      const curve = d.generator.diffusion.curves[near.curve];
      curve.constraints = placeConstraint(curve.constraints, added);
    });
  },
  "move-control": (start, end) => {
    const near = pending.control;
    pending.control = null;
    if (!near) return refuse("press on a curve's control point (shown as a square or a dot)");
    const by = [end[0] - start[0], end[1] - start[1]];
    editDoc((d) => {
      const curve = d.generator.diffusion.curves[near.curve];
      curve.points = moveControl(curve.points, near.k, by, roundWorld);
    });
  },
};

// Re-editing what was drawn: a feature's points and a region's corners dragged, a feature or a
// region removed, a region's height set. A change the generator refuses (a region crossing
// another) comes back as a refusal and is undone.
const SHAPE_TOOLS = {
  "move-feature": (start, end) => {
    const near = pending.shape;
    pending.shape = null;
    if (!near) return refuse("press on a point of a ridge, riverbed, cliff, hill crest or crack (shown as squares)");
    editDoc((d) => movePresetPoint(d.generator.diffusion.presets, near.item, roundWorld(end)));
  },
  "remove-feature": (start) => {
    const g = doc.generator.diffusion;
    const lines = (g.presets || []).map((preset, k) => ({ key: "presets", k, lines: presetLines(preset) }))
      .concat((g.curves || []).map((curve, k) => ({ key: "curves", k, lines: [centreLine(curve.points)] })));
    const near = lines
      .map((f) => ({ ...f, distance: Math.min(...f.lines.map((line) => distanceToLine(line, start))) }))
      .filter((f) => f.distance * view.scale <= 16)
      .sort((a, b) => a.distance - b.distance)[0];
    if (!near) return refuse("click on a drawn feature or Bézier curve to remove it");
    editDoc((d) => d.generator.diffusion[near.key].splice(near.k, 1));
  },
  "move-corner": (start, end) => {
    const near = pending.shape;
    pending.shape = null;
    if (!near) return refuse("press on a region's corner (shown as squares)");
    editDoc((d) => (d.generator.contours.regions[near.item.region].polygon.exterior[near.item.k] = roundWorld(end)));
  },
  "region-height": (start) => {
    const k = regionAt(doc.generator.contours.regions, start);
    if (k < 0 || doc.generator.contours.regions[k].depression) return refuse("click inside a region (not a depression) to give it the height setting");
    editDoc((d) => (d.generator.contours.regions[k].height = Number($("height").value)));
  },
  "remove-region": (start) => {
    const k = regionAt(doc.generator.contours.regions, start);
    if (k < 0) return refuse("click inside a region or depression to remove it");
    editDoc((d) => d.generator.contours.regions.splice(k, 1));
  },
};

/** Small squares on the points `{ q }` a drag can move. */
function drawHandles(ctx, points) {
  ctx.fillStyle = "#fff";
  for (const { q } of points) {
    const [x, y] = worldToCanvas(q);
    ctx.fillRect(x - 3, y - 3, 7, 7);
  }
}

/** A constraint at `u` from the settings: the groups ticked, with their values. */
function curveConstraint(u) {
  const c = { u: Math.max(0, Math.min(1, Number(u.toFixed(4)))) };
  if ($("c-elevation").checked) c.elevation = { h: Number($("height").value), r: 0 };
  if ($("c-slope").checked) {
    const angle = (id) => Math.max(-89, Math.min(89, Number($(id).value) || 0));
    c.slope = { a: radius(), b: radius(), theta: angle("c-theta"), phi: angle("c-phi") };
  }
  if ($("c-noise").checked) {
    const roughness = Math.max(0, Math.min(1, Number($("c-roughness").value) || 0));
    c.noise = { amplitude: Math.abs(Number($("c-amplitude").value)) || 0, roughness };
  }
  return c;
}

function hasConstraint(c) {
  return Boolean(c.elevation || c.slope || c.noise);
}

/** Says why a gesture did nothing, and redraws. */
function refuse(why) {
  $("message").textContent = why;
  drawMap();
}

/** The scene's curve nearest `p` within 16 pixels: `{ curve, u }`, or null. */
function nearestCurve(p) {
  let best = null;
  (doc.generator.diffusion.curves || []).forEach((curve, k) => {
    const near = nearestOnLine(centreLine(curve.points), p);
    if (near.distance * view.scale <= 16 && (!best || near.distance < best.distance)) best = { curve: k, u: near.u, distance: near.distance };
  });
  return best;
}

/** The control point nearest `p` within 12 pixels: `{ curve, k }`, or null. */
function nearestControl(p) {
  const points = (doc.generator.diffusion.curves || []).flatMap((curve, c) => curve.points.map((q, k) => ({ curve: c, k, q })));
  const found = nearest(points, p, 12, (point) => point.q);
  return found && { curve: found.item.curve, k: found.item.k };
}

/** Each curve's control polygon (anchors as squares, handles as dots) and its constraint
 * points, labelled with their elevation. */
function drawCurveHandles(ctx, curves) {
  for (const curve of curves) {
    ctx.strokeStyle = "rgba(255, 255, 255, 0.35)";
    polyline(ctx, curve.points, false);
    ctx.fillStyle = "#fff";
    curve.points.forEach((q, k) => {
      const [x, y] = worldToCanvas(q);
      if (k % 3 === 0 || curve.points.length === 2) ctx.fillRect(x - 3, y - 3, 7, 7);
      else ctx.fillRect(x - 2, y - 2, 4, 4);
    });
    const line = centreLine(curve.points);
    ctx.fillStyle = "rgba(255, 220, 60, 1)";
    for (const c of curve.constraints || []) {
      const [x, y] = worldToCanvas(pointAt(line, c.u));
      ctx.beginPath();
      ctx.arc(x, y, 4, 0, 2 * Math.PI);
      ctx.fill();
      if (c.elevation) ctx.fillText(`${c.elevation.h.toFixed(0)} m`, x + 5, y + 12);
    }
  }
}

// Vector terrain tools from a press at `a` released at `b` (`n` points dragged).
const GAUSSIAN_TOOLS = {
  stamp: (a, b, n) => n >= 2 && {
    op: "stamp", region: circle(a), placement: { to: b, rotation: 0, scale: 1 }, mode: "copy", damping: radius() / 10,
  },
  twist: (a) => ({ op: "twist", region: circle(a), angle: 1.0, falloff: radius() / 2 }),
  squeeze: (a, b, n) => n >= 2 && { op: "squeeze", region: circle(a), by: [b[0] - a[0], b[1] - a[1]], falloff: radius() / 2 },
  "copy-landform": (a) => ({ op: "copy", region: circle(a), name: `landform-${copies().length + 1}` }),
  "paste-landform": (a) => copies().length > 0 && {
    op: "paste", landform: copies()[copies().length - 1], footprint: radius(),
    placement: { to: a, rotation: 0, scale: 1 }, damping: radius() / 10,
  },
  "raise-crest": (a) => ({ op: "raise_crest", near: a, factor: 0.4 }),
  "move-crest": (a, b, n) => {
    if (n < 2) return false;
    const node = nearestNode(a);
    const by = [b[0] - a[0], b[1] - a[1]];
    return node === null ? { op: "move_crest", near: a, by } : { op: "move_crest", node, by };
  },
};

/** A circular selection at `p` of the radius setting. */
function circle(p) {
  return { shape: "circle", center: p, radius: radius() };
}

/** The landforms the scene's copy tools keep, in order. */
function copies() {
  return doc.generator.gaussian.operations.filter((op) => op.op === "copy" || op.op === "cut").map((op) => op.name);
}

// The crest skeleton of the current vector terrain (exported by a full run when the crest tool is
// chosen): its nodes, whose ids `move_crest` takes.
let skeleton = null;

async function loadSkeleton() {
  skeleton = null;
  if (generatorKind() !== "gaussian" || tool() !== "move-crest") return;
  const exportHeaders = { ...jsonBody, "x-relief-session": `${session}-skeleton` };
  const response = await fetch("/api/export/skeleton.geojson", { method: "POST", body: JSON.stringify(doc), headers: exportHeaders });
  if (!response.ok) return;
  const geojson = await response.json();
  skeleton = geojson.features
    .filter((f) => f.geometry.type === "Point")
    .map((f) => ({ id: f.properties.id, position: f.geometry.coordinates }));
  document.body.dataset.skeleton = String(skeleton.length);
  drawMap();
}

/** The id of the skeleton node nearest `p` within 12 pixels, or null. */
function nearestNode(p) {
  const found = skeleton && nearest(skeleton, p, 12, (node) => node.position);
  return found ? found.item.id : null;
}

function drawSkeleton(ctx) {
  ctx.fillStyle = "rgba(120, 255, 220, 0.95)";
  for (const node of skeleton) {
    const [x, y] = worldToCanvas(node.position);
    ctx.beginPath();
    ctx.arc(x, y, 3, 0, 2 * Math.PI);
    ctx.fill();
  }
}

/** At most 24 points of a dragged course, at least 1/40 of the map apart. */
function simplified(points) {
  const e = result.extent;
  const spacing = Math.max(e.max[0] - e.min[0], e.max[1] - e.min[1]) / 40;
  const kept = [points[0]];
  for (const p of points.slice(1)) {
    const last = kept[kept.length - 1];
    if (Math.hypot(p[0] - last[0], p[1] - last[1]) >= spacing) kept.push(p);
  }
  const end = points[points.length - 1];
  if (kept[kept.length - 1] !== end) kept.push(end);
  const step = Math.ceil(kept.length / 24);
  return kept.filter((_, k) => k % step === 0 || k === kept.length - 1);
}

function closeRegion() {
  const t = tool();
  if ((t !== "region" && t !== "depression") || pending.points.length < 3) return;
  // A double-click adds its point twice; drop repeats.
  const ring = pending.points.filter((p, k, all) => k === 0 || p[0] !== all[k - 1][0] || p[1] !== all[k - 1][1]);
  pending.points = [];
  const region = t === "depression" ? { polygon: { exterior: ring }, depression: true } : { polygon: { exterior: ring }, height: Number($("height").value) };
  editDoc((d) => d.generator.contours.regions.push(region));
}

// ---------------------------------------------------------------------------------------------
// Files: templates, save, load.

async function loadTemplate(name) {
  const response = await fetch(`/api/templates/${name}`);
  past.undo.length = 0;
  past.redo.length = 0;
  doc = null;
  setDoc(await response.json(), false);
  markClean();
}

async function save() {
  const name = $("name").value.trim();
  const response = await fetch(`/api/scenes/${encodeURIComponent(name)}`, { method: "PUT", body: JSON.stringify(doc), headers: jsonBody });
  if (response.ok) {
    markClean();
    setState(document.body.dataset.state, `saved ${name}`);
    await listScenes();
  } else {
    const body = await response.json();
    $("message").textContent = (body.path ? body.path + ": " : "") + body.error;
  }
}

async function listScenes() {
  const { scenes } = await (await fetch("/api/scenes")).json();
  const select = $("load");
  select.length = 1;
  for (const name of scenes) select.add(new Option(name, name));
}

async function load(name) {
  const response = await fetch(`/api/scenes/${encodeURIComponent(name)}`);
  if (!response.ok) return;
  $("name").value = name;
  setDoc(await response.json());
  markClean();
}

/** Generates the scene in full on the server and downloads the chosen output. */
async function exportOutput() {
  const file = $("export").value;
  setState(document.body.dataset.state, `exporting ${file}…`);
  // Its own job: an edit meanwhile does not cancel it.
  const exportHeaders = { ...jsonBody, "x-relief-session": `${session}-export` };
  const response = await fetch(`/api/export/${file}`, { method: "POST", body: JSON.stringify(doc), headers: exportHeaders });
  if (!response.ok) {
    const body = await response.json();
    $("message").textContent = (body.path ? body.path + ": " : "") + body.error;
    return;
  }
  const link = document.createElement("a");
  link.href = URL.createObjectURL(await response.blob());
  // An engine's files (heightmaps, splat maps, the import numbers) come as one zip.
  link.download = file.startsWith("engine/") ? `terrain-${file.slice(7)}.zip` : file;
  link.click();
  setTimeout(() => URL.revokeObjectURL(link.href), 10000);
  setState(document.body.dataset.state, `exported ${file}`);
}

function applyText() {
  try {
    setDoc(JSON.parse($("scene").value));
  } catch (error) {
    $("message").textContent = "scene JSON: " + error.message;
  }
}

// Uploads: a DEM or an image into the workspace, then a scene that reads it.

let uploaded = null;

async function upload() {
  const file = $("upload").files[0];
  if (!file) return;
  const response = await fetch(`/api/files/${encodeURIComponent(file.name)}`, { method: "PUT", body: file });
  if (!response.ok) {
    $("message").textContent = (await response.json()).error;
    return;
  }
  uploaded = file.name;
  setState(document.body.dataset.state, `uploaded ${file.name}`);
  for (const id of ["vectorize", "synthesize", "trace", "open-dem", "labels"]) $(id).disabled = false;
}

function startFrom(scene) {
  past.undo.length = 0;
  past.redo.length = 0;
  doc = null;
  setDoc(scene, false);
}

/** Shows the uploaded DEM itself as the current result (the scene is unchanged). */
async function openUpload() {
  generation++;
  const response = await fetch(`/api/files/${encodeURIComponent(uploaded)}/open`, { method: "POST", headers: jsonBody });
  const body = await response.json();
  if (!response.ok) {
    $("message").textContent = body.error;
    return;
  }
  const z = new Float32Array(await (await fetch(`/api/results/${body.id}/elevation`)).arrayBuffer());
  showResult(Object.assign(body, { z }));
  viewingUpload = true;
  setState("idle", `${uploaded}: ${body.width}×${body.height}`);
}

function vectorizeUpload() {
  startFrom({
    version: 1, seed: 1, description: `${uploaded}, vectorized into generalized Gaussians (Perche et al. 2025).`,
    generator: { gaussian: { source: { kind: "dem", path: uploaded, primitives: 1000, iterations: 40, resolution: 192 }, operations: [] } },
    reconstruction: { resolution: [512, 512] },
  });
}

function synthesizeUpload() {
  startFrom({
    version: 1, seed: 1, description: `A terrain synthesized from ${uploaded}'s peaks and divide tree (Argudo et al. 2019).`,
    domain: { min: [0, 0], max: [20000, 20000] },
    generator: { orometry: { source: { kind: "dem", path: uploaded, min_prominence: 30 } } },
    reconstruction: { resolution: [400, 400] },
  });
}

function labelUpload() {
  startFrom({
    version: 1, seed: 1, description: `${uploaded}'s colour areas as nested regions (the contours paper's label images).`,
    generator: { contours: {
      label_image: { path: uploaded, extent: { min: [0, 0], max: [10000, 10000] } },
      histogram: { uniform: { min: 0, max: Math.abs(Number($("height").value)) || 1000 } },
      particles: 20000,
    } },
    reconstruction: { resolution: [512, 512] },
  });
}

function traceUpload() {
  if (generatorKind() !== "island") {
    $("message").textContent = "Trace as coast works on an island scene: start one with New → island.";
    return;
  }
  editDoc((d) => (d.generator.island.coastline_image = { path: uploaded }));
}

// ---------------------------------------------------------------------------------------------

async function start() {
  const info = await (await fetch("/api/info")).json();
  for (const name of info.templates) $("template").add(new Option(name, name));
  $("new").onclick = () => loadTemplate($("template").value);
  $("undo").onclick = undo;
  $("redo").onclick = redo;
  $("save").onclick = save;
  $("load").onchange = (e) => e.target.value && load(e.target.value);
  $("generate").onclick = generate;
  $("cancel").onclick = cancel;
  $("apply").onclick = applyText;
  $("export-button").onclick = exportOutput;
  $("format").onchange = () => result && downloadLinks();
  $("upload").onchange = upload;
  $("vectorize").onclick = vectorizeUpload;
  $("synthesize").onclick = synthesizeUpload;
  $("trace").onclick = traceUpload;
  $("labels").onclick = labelUpload;
  $("open-dem").onclick = openUpload;
  $("show-peaks").onchange = () => (peaks ? drawMap() : loadPeaks());
  $("min-prominence").onchange = loadPeaks;
  for (const radio of document.querySelectorAll('input[name="tool"]')) {
    radio.addEventListener("change", () => (radio.value === "move-crest" ? loadSkeleton() : drawMap()));
  }
  $("filters").onclick = () => editDoc((d) => d.generator.island.operations.push({ add_filters: { coverage: 1 } }));
  const map = $("map");
  map.addEventListener("pointerdown", onPointerDown);
  map.addEventListener("pointermove", onPointerMove);
  map.addEventListener("pointerup", onPointerUp);
  map.addEventListener("dblclick", closeRegion);
  document.addEventListener("keydown", (e) => {
    if (e.target.tagName === "TEXTAREA" || e.target.tagName === "INPUT") return;
    if ((e.ctrlKey || e.metaKey) && e.key === "z") { e.preventDefault(); undo(); }
    if ((e.ctrlKey || e.metaKey) && e.key === "y") { e.preventDefault(); redo(); }
    if (e.key === "Enter") closeRegion();
    if (e.key === "Escape") { pending.points = []; drawMap(); }
  });
  setup3d($("view3d"));
  await listScenes();
  const draft = readDraft();
  if (draft) {
    $("name").value = draft.name || "";
    restored = true;
    startFrom(JSON.parse(draft.doc));
  } else {
    await loadTemplate("demo");
  }
}

// For the browser tests and the console.
window.studio = {
  get doc() { return doc; },
  get result() { return result; },
  get skeleton() { return skeleton; },
  worldToCanvas, canvasToWorld,
  timings, setDoc, editDoc, undo, redo, generate, cancel, save, load, loadTemplate, closeRegion, exportOutput,
};

start();
