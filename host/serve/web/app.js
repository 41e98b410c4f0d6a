// The page: a client of the server's JSON-RPC API like any script. It watches until a person takes
// control; the E-stop (button, Space, Escape) works for watchers too.
"use strict";

const $ = (id) => document.getElementById(id);
const PLOT_SECONDS = 10;
let ws = null, nextId = 1, me = null, controls = false, board = null, controllerNow = null;
const pending = new Map();
const fingerPlots = [], linePlots = [], targets = [];

/// The API and its messages number fingers and lines from 0, as programs index them; this page,
/// like the command line, shows them from 1: "finger 0 does not exist (this board has fingers 0
/// to 4)" is shown as "finger 1 does not exist (this board has fingers 1 to 5)".
function fromOne(text) {
  return text.replace(/\b(fingers?|lines?) (\d+)(?: to (\d+))?/g, (_, what, a, b) =>
    `${what} ${Number(a) + 1}${b === undefined ? "" : ` to ${Number(b) + 1}`}`);
}

function say(text) { $("message").textContent = fromOne(text || ""); }

function call(method, params = {}) {
  return new Promise((resolve, reject) => {
    if (!ws || ws.readyState !== WebSocket.OPEN) return reject(new Error("not connected"));
    const id = nextId++;
    pending.set(id, { resolve, reject });
    ws.send(JSON.stringify({ jsonrpc: "2.0", id, method, params }));
  });
}

async function act(method, params) {
  try {
    const result = await call(method, params);
    say("");
    return result;
  } catch (e) {
    say(`${method}: ${e.message}`);
    return null;
  }
}

function showControl(controller, name) {
  controllerNow = controller;
  controls = controller !== null && controller === me;
  $("control").textContent = controls ? "you control the board"
    : controller === null ? "nobody controls the board" : `watching: ${name} controls the board`;
  $("take").hidden = controls;
  $("take").textContent = controller === null ? "Take control" : "Take control from it";
  for (const id of ["give", "clear", "release"]) $(id).hidden = !controls;
  for (const b of document.querySelectorAll(".needs-control")) b.disabled = !controls;
}

function fingerCard(f, i) {
  const unit = f.unit, card = document.createElement("div");
  card.className = "card";
  card.innerHTML = `<h3><span>Finger ${i + 1} <small>(${f.kind}, ${unit})</small></span>
    <span id="out${i}">—</span></h3><canvas id="fplot${i}"></canvas>
    <div class="legend"><span class="me">— output (estimated)</span> <span class="tg">- - target</span>
      <span class="tr" hidden>— true output (simulator)</span></div>
    <div class="controls">
      <button class="needs-control" data-level="0">L0</button>
      <button class="needs-control" data-level="1">L1</button>
      <button class="needs-control" data-level="2">L2</button>
      <input id="val${i}" type="number" step="any" aria-label="value for finger ${i + 1}">
      <select id="unit${i}">
        <option value="${unit === "mm" ? "mm" : "n_per_mm"}">${unit}</option>
        <option value="normalized">0..1</option><option value="kpa">kPa (raw)</option>
      </select>
      <button class="needs-control" id="set${i}">Set</button>
    </div>`;
  card.querySelectorAll("[data-level]").forEach((b) =>
    b.addEventListener("click", () => setFinger(i, { level: Number(b.dataset.level) })));
  card.querySelector(`#set${i}`).addEventListener("click", () => {
    const v = Number($(`val${i}`).value);
    if ($(`val${i}`).value === "" || !Number.isFinite(v)) return say("enter a number first");
    setFinger(i, { [$(`unit${i}`).value]: v });
  });
  return card;
}

function lineCard(l, i) {
  const card = document.createElement("div");
  card.className = "card";
  card.innerHTML = `<h3><span>Line ${i + 1} <small>(${l.kind}, ${l.limit_min_pa / 1000} … ${l.limit_max_pa / 1000} kPa)</small></span>
    <span id="meas${i}">—</span></h3><canvas id="lplot${i}"></canvas>
    <div class="legend"><span class="me">— measured</span> <span class="sp">- - setpoint</span> (kPa)</div>
    <div class="controls"><input id="kpa${i}" type="number" step="any" aria-label="kPa for line ${i + 1}">
      <button class="needs-control" id="line${i}">Set kPa (raw)</button></div>`;
  card.querySelector(`#line${i}`).addEventListener("click", () => {
    const v = Number($(`kpa${i}`).value);
    if ($(`kpa${i}`).value === "" || !Number.isFinite(v)) return say("enter a pressure first");
    act("board.lines.set", { setpoints: [{ line: i, kpa: v }] });
  });
  return card;
}

async function setFinger(i, target) {
  const result = await act("board.set", { targets: [{ finger: i, ...target }] });
  if (!result) return;
  const a = result.applied[0];
  targets[i] = a.raw ? NaN : a.target;
  say(`Finger ${i + 1}: ${a.raw ? "raw setpoints" : `target ${a.target} ${a.unit}`}`);
}

function build(info) {
  board = info;
  $("board").textContent = `${info.board.configuration} (${info.board.kind}, firmware ${info.board.firmware}) — ${info.device}`;
  const fingers = $("fingers"), lines = $("lines");
  fingers.replaceChildren(); lines.replaceChildren();
  fingerPlots.length = linePlots.length = targets.length = 0;
  info.fingers.forEach((f, i) => {
    fingers.appendChild(fingerCard(f, i));
    fingerPlots.push(new Plot($(`fplot${i}`), [{ color: "#1565c0" }, { color: "#888", dashed: true }, { color: "#2e7d32" }], PLOT_SECONDS,
      f.unit === "mm" ? 0.5 : 0.1));
    targets.push(NaN);
  });
  info.lines.forEach((l, i) => {
    lines.appendChild(lineCard(l, i));
    linePlots.push(new Plot($(`lplot${i}`), [{ color: "#888", dashed: true }, { color: "#1565c0" }], PLOT_SECONDS, 5));
  });
}

function onTelemetry(p) {
  const s = p.samples;
  $("faults").textContent = p.faults.length ? p.faults.join(", ") : "none";
  $("faults").className = p.faults.length ? "latched" : "";
  s.board_time_us.forEach((t, k) => {
    s.finger_output[k].forEach((v, f) => {
      fingerPlots[f]?.add(0, t, v);
      if (Number.isFinite(targets[f])) fingerPlots[f]?.add(1, t, targets[f]);
    });
    s.setpoint_pa[k].forEach((v, l) => linePlots[l]?.add(0, t, v / 1000));
    s.measured_pa[k].forEach((v, l) => linePlots[l]?.add(1, t, v / 1000));
  });
  if (p.finger_truth) {  // a simulated board: what the finger really did, beside the estimate
    p.finger_truth.forEach((v, f) => fingerPlots[f]?.add(2, p.truth_board_time_us, v));
    document.querySelectorAll(".legend .tr").forEach((e) => (e.hidden = false));
  }
  const last = s.board_time_us.length - 1;
  if (last < 0) return;
  s.finger_output[last].forEach((v, f) => (fingerNow.output[f] = v));
  s.finger_output[last].forEach((v, f) => { const e = $(`out${f}`); if (e) e.textContent = `${v.toFixed(3)} ${board.fingers[f].unit}`; });
  s.measured_pa[last].forEach((v, l) => { const e = $(`meas${l}`); if (e) e.textContent = `${(v / 1000).toFixed(2)} kPa`; });
}

function onMessage(event) {
  const m = JSON.parse(event.data);
  if (m.id !== undefined && pending.has(m.id)) {
    const { resolve, reject } = pending.get(m.id);
    pending.delete(m.id);
    return m.error ? reject(new Error(m.error.message)) : resolve(m.result);
  }
  if (m.method === "notify_telemetry") onTelemetry(m.params);
  else if (m.method === "notify_scene") onSceneState(m.params);
  else if (m.method === "notify_control") {
    showControl(m.params.controller, m.params.controller_name);
    if (m.params.board_released) say(`board released: ${m.params.reason}`);
  } else if (m.method === "notify_board_event") say(m.params.message);
}

function connect() {
  ws = new WebSocket(`ws://${location.host}/websocket`);
  ws.onmessage = onMessage;
  ws.onopen = async () => {
    $("link").textContent = "connected"; $("link").className = "state ok";
    try {
      me = (await call("server.connection.identify", { client_name: "page" })).client;
      build(await call("board.info"));
      const info = await call("server.info");
      showControl(info.controller, info.controller_name);
      await call("telemetry.subscribe", { updates_per_s: 30, sample_rate_hz: 100 });
      showScene(await call("scene.info"));
    } catch (e) { say(e.message); }
  };
  ws.onclose = () => {
    // A page that comes back is a watcher: the server released the board if this one controlled.
    $("link").textContent = "disconnected, reconnecting"; $("link").className = "state bad";
    for (const { reject } of pending.values()) reject(new Error("disconnected"));
    pending.clear();
    showControl(null, "");
    setTimeout(connect, 1000);
  };
}

function estop() {
  $("estop").classList.add("pressed");
  setTimeout(() => $("estop").classList.remove("pressed"), 300);
  act("board.estop").then((r) => r && say("E-stop: every line safe until Clear faults and new targets"));
}

$("estop").addEventListener("click", estop);
window.addEventListener("keydown", (e) => {
  if (e.code === "Space" || e.key === "Escape") { e.preventDefault(); estop(); }
}, true);
$("take").addEventListener("click", () =>
  act("control.take", { force: controllerNow !== null }));
$("give").addEventListener("click", () => act("control.release"));
$("clear").addEventListener("click", () => act("board.clear"));
$("release").addEventListener("click", () => act("board.release"));
(function frame() {
  for (const p of fingerPlots.concat(linePlots)) p.draw();
  drawScene();
  requestAnimationFrame(frame);
})();
setupScene();
connect();
