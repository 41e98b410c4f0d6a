// The scene view: the tissue's map, each finger an avatar (the thesis's red, blue and green
// spheres) where the hand puts it, driven by pen, mouse or touch through Pointer Events — the
// pressure the device reports (a mouse reports 0.5 while pressed) times the full press in newtons.
"use strict";

const FINGER_COLOURS = ["#d32f2f", "#1565c0", "#2e7d32", "#f9a825", "#6a1b9a", "#00838f", "#5d4037", "#ad1457"];
const COLOUR_NAMES = ["red", "blue", "green", "yellow", "purple", "teal", "brown", "pink"];
let scene = null, sceneState = null, sceneImage = null, scenePress = null;
const fingerNow = { output: [], truth: [] };  // the newest telemetry, per board finger

/// Blue → cyan → yellow → red over t in 0 … 1, as the library's scene SVG colours a map.
function mapColour(t) {
  t = Math.min(1, Math.max(0, Number.isFinite(t) ? t : 0));
  const [r, g, b] = t < 1 / 3 ? [0, 3 * t, 1] : t < 2 / 3 ? [3 * t - 1, 1, 2 - 3 * t] : [1, 3 - 3 * t, 0];
  return [r * 255, g * 255, b * 255];
}

/// Where the map and the fingers are drawn: a margin wide enough for fingers beside the hand.
function sceneGeometry() {
  const c = $("scene-map"), t = scene.tissue;
  let reach = scene.layout.contact_diameter_mm / 2 + 2;
  for (const [dx, dy] of scene.layout.places_mm) reach = Math.max(reach, Math.abs(dx), Math.abs(dy));
  const wmm = t.extent_mm[0] + 2 * reach, hmm = t.extent_mm[1] + 2 * reach;
  const scale = Math.min(c.clientWidth / wmm, 420 / hmm);
  return { scale, reach, width: c.clientWidth, height: Math.ceil(hmm * scale) };
}

/// A position on the tissue (mm, y upwards) as a point on the canvas, and back.
function scenePixel(x, y) {
  const g = sceneGeometry();
  return [(x + g.reach) * g.scale, g.height - (y + g.reach) * g.scale];
}
function sceneMm(px, py) {
  const g = sceneGeometry();
  return [px / g.scale - g.reach, (g.height - py) / g.scale - g.reach];
}

function showScene(info) {
  const choice = $("scene-choice"), was = choice.value;
  choice.replaceChildren();
  for (const p of info.presets) choice.add(new Option(`preset: ${p}`, `preset:${p}`));
  for (const s of info.server_scenes) choice.add(new Option(`server scene: ${s}`, `server:${s}`));
  if (was) choice.value = was;
  scene = info.loaded ? info : null;
  $("scene-name").textContent = scene ? `${scene.name} — ${scene.tissue.name} (${scene.tissue.unit}), ` +
    `${scene.tissue.extent_mm[0]} × ${scene.tissue.extent_mm[1]} mm` : "no scene loaded";
  sceneImage = null;
  if (!scene) return;
  const t = scene.tissue, ny = t.values.length, nx = t.values[0].length;
  const [lo, hi] = t.range, img = new ImageData(nx, ny);
  t.values.forEach((row, j) => row.forEach((v, i) => {
    const k = ((ny - 1 - j) * nx + i) * 4, [r, g, b] = mapColour(hi > lo ? (v - lo) / (hi - lo) : 0);
    img.data.set([r, g, b, 255], k);
  }));
  sceneImage = document.createElement("canvas");
  sceneImage.width = nx; sceneImage.height = ny;
  sceneImage.getContext("2d").putImageData(img, 0, 0);
}

/// The document a preset is loaded as: the thesis's right triangle over the board's first three
/// fingers (a row over fewer), its fingertip-stress rule.
function presetScene(preset) {
  const n = Math.min(3, board.fingers.length);
  return {
    schema: "palpa-scene", schema_version: 1, name: `${preset} from the page`, tissue: { preset },
    layout: n === 3 ? { kind: "right-triangle", spacing_mm: 15, contact_diameter_mm: 4 }
      : { kind: "row", count: n, spacing_mm: 15, contact_diameter_mm: 4 },
    fingers: [...Array(n).keys()],
    rule: { contrast: 1, contact_force_n: 0.05, pneumatic: { mapping: "fingertip-stress", range_kpa: [5.91, 11.154] } },
  };
}

async function loadScene() {
  const [kind, name] = $("scene-choice").value.split(/:(.*)/s);
  const info = await act("scene.load", kind === "server" ? { name } : { scene: presetScene(name) });
  if (info) showScene(info);
}

function onSceneState(p) {
  sceneState = p;
  if (p.finger_truth) p.finger_truth.forEach((v, f) => (fingerNow.truth[f] = v));
  $("scene-running").textContent = p.running ? "running" : "stopped";
  if (p.error) say(`scene stopped: ${p.error}`);
  const rows = (p.fingers || []).map((f, k) => {
    const out = fingerNow.output[f.finger], tru = fingerNow.truth[f.finger];
    return `<div class="scene-finger"><span class="dot f${k % 8}"></span>
      Finger ${f.finger + 1} (${COLOUR_NAMES[k % 8]}): ${f.touching ? `touches ${f.value.toPrecision(3)} ${scene ? scene.tissue.unit : ""}` : "touches nothing"},
      target <b>${f.target.toFixed(3)} ${f.unit}</b>, output ${out === undefined ? "—" : out.toFixed(3)}
      ${tru === undefined ? "" : `, true ${tru.toFixed(3)}`} ${f.unit}</div>`;
  });
  $("scene-fingers").innerHTML = rows.join("");
}

function sendPointer(e, pressed) {
  if (!scene || !controls || !sceneState || !sceneState.running) return;
  const r = $("scene-map").getBoundingClientRect();
  const [x, y] = sceneMm(e.clientX - r.left, e.clientY - r.top);
  const full = Number($("scene-full").value) || 0;
  const force = pressed ? Math.min(scene.max_force_n, Math.max(0, e.pressure * full)) : 0;
  scenePress = pressed ? [x, y, force] : null;
  // A notification: no answer, and the server feeds only the newest sample it holds.
  if (ws && ws.readyState === WebSocket.OPEN)
    ws.send(JSON.stringify({ jsonrpc: "2.0", method: "scene.pointer", params: { x_mm: x, y_mm: y, force_n: force } }));
}

function drawScene() {
  const c = $("scene-map"), ctx = c.getContext("2d");
  if (!scene || !sceneImage) { c.height = 0; return; }
  const g = sceneGeometry();
  if (c.width !== g.width || c.height !== g.height) { c.width = g.width; c.height = g.height; }
  ctx.clearRect(0, 0, c.width, c.height);
  const [x0, y0] = scenePixel(0, scene.tissue.extent_mm[1]);
  ctx.drawImage(sceneImage, x0, y0, scene.tissue.extent_mm[0] * g.scale, scene.tissue.extent_mm[1] * g.scale);
  if (!sceneState || !sceneState.input) return;
  const { x_mm, y_mm, force_n } = sceneState.input;
  const radius = Math.max(7, scene.layout.contact_diameter_mm / 2 * g.scale);
  scene.layout.places_mm.forEach(([dx, dy], k) => {
    const [px, py] = scenePixel(x_mm + dx, y_mm + dy), f = (sceneState.fingers || [])[k];
    const sphere = ctx.createRadialGradient(px - radius / 3, py - radius / 3, radius / 6, px, py, radius);
    sphere.addColorStop(0, "#fff"); sphere.addColorStop(0.35, FINGER_COLOURS[k % 8]); sphere.addColorStop(1, "#222");
    ctx.fillStyle = sphere; ctx.beginPath(); ctx.arc(px, py, radius, 0, 2 * Math.PI); ctx.fill();
    ctx.lineWidth = f && f.touching ? 3 : 1; ctx.strokeStyle = f && f.touching ? "#fff" : "#000"; ctx.stroke();
    ctx.fillStyle = "#000"; ctx.font = "12px sans-serif";
    if (f) ctx.fillText(`${f.finger + 1}: ${f.target.toFixed(2)} ${f.unit}`, px + radius + 3, py + 4);
  });
  ctx.fillStyle = "#000"; ctx.fillText(`${force_n.toFixed(2)} N`, 4, 14);
}

function setupScene() {
  const c = $("scene-map");
  c.addEventListener("pointerdown", (e) => { c.setPointerCapture(e.pointerId); sendPointer(e, true); });
  c.addEventListener("pointermove", (e) => { if (scenePress) sendPointer(e, true); });
  for (const end of ["pointerup", "pointercancel"]) c.addEventListener(end, (e) => sendPointer(e, false));
  $("scene-load").addEventListener("click", loadScene);
  $("scene-start").addEventListener("click", () => act("scene.start"));
  $("scene-stop").addEventListener("click", () => act("scene.stop"));
}
