// The experimenter's view: choose a study and a participant, start and stop the session, and
// follow it — each trial's condition, answer, correctness and time as it happens, and the
// provenance the records carry. Starting needs control of the board (the first click takes it).
"use strict";

let me = null, controller = null, fileStudy = null, triggerLine = null;
const rows = new Map();

function say(text) { $("e-message").textContent = text || ""; }

function showControl(c, name) {
  controller = c;
  $("e-control").textContent = c === null ? "nobody controls the board"
    : c === me ? "you control the board" : `${name} controls the board`;
  $("e-take").hidden = c === me;
}

function answerText(r) {
  if (!r.answer) return "";
  if (r.kind === "staircase") return `finger ${r.answer.fingers.indexOf(true) + 1}`;
  const f = r.answer.fingers.flatMap((m, k) => (m ? [k + 1] : []));
  return r.answer.tumour ? `tumour: ${f.join(" ")}` : "none";
}

function row(trial) {
  if (!rows.has(trial)) {
    const tr = document.createElement("tr");
    tr.innerHTML = "<td></td>".repeat(7);
    tr.cells[0].textContent = trial + 1;
    $("e-trials").tBodies[0].appendChild(tr);
    rows.set(trial, tr);
  }
  return rows.get(trial);
}

function fill(trial, values) {
  const tr = row(trial);
  values.forEach((v, k) => { if (v !== undefined) tr.cells[k + 1].textContent = v; });
}

function record(r) {
  fill(r.index, [r.block, r.condition + (r.practice ? " (practice)" : ""), answerText(r),
    r.correct ? "yes" : "no", r.time_ms, r.settled_board_ms]);
  row(r.index).className = r.correct ? "right" : "wrong";
}

function session(s) {
  rows.clear();
  $("e-trials").tBodies[0].replaceChildren();
  if (!s || !s.study) return;
  (s.records || []).forEach(record);
  status(s);
  const p = s.provenance, dl = $("e-provenance");
  dl.replaceChildren();
  if (!p) return;
  const facts = [["board", p.board], ["firmware", p.firmware_version], ["catalog", p.catalog_hash],
    ["configuration CRC", p.config_crc], ["palpa", p.palpa_version],
    ["calibration files", Object.keys(p.calibration_files || {}).length || "none (nominal)"],
    ["simulated board", p.sim ? `seed ${p.sim.seed}, unit ${p.sim.unit}` : "no"]];
  for (const [k, v] of facts) {
    const dt = document.createElement("dt"), dd = document.createElement("dd");
    dt.textContent = k;
    dd.textContent = v === undefined ? "—" : String(v);
    dl.append(dt, dd);
  }
}

function status(s) {
  const n = (s.records || []).length, total = (s.order || []).length;
  $("e-status").textContent = `${s.study}, participant ${s.participant} (${s.out_dir}): ` +
    (s.running ? `running, ${n} of ${total} trials` : s.complete ? "complete" : `ended: ${s.message}`);
}

let current = null;
function onStudy(e) {
  if (e.event === "started") { current = e.session; session(current); }
  else if (e.event === "trial_started") {
    fill(e.trial, [e.block, e.condition + (e.practice ? " (practice)" : ""), "…"]);
  } else if (e.event === "trigger") {
    $("e-trigger").textContent = `trigger: ${e.kind}, trial ${e.trial + 1}, board ${e.board_ms.toFixed(0)} ms` +
      (triggerLine ? `, pulsed on ${triggerLine}` : "");
  } else if (e.event === "trial_answered") {
    record(e.record);
    if (current) { current.records.push(e.record); status(current); }
  } else if (e.event === "finished") {
    if (current) { Object.assign(current, { running: false, complete: e.complete, message: e.message }); status(current); }
  } else if (e.event === "note" || e.event === "refused" || e.event === "stopping") {
    say(e.message || `stopping: ${e.reason}`);
  }
}

async function act(method, params) {
  try { const r = await rpc.call(method, params); say(""); return r; }
  catch (e) { say(`${method}: ${e.message}`); return null; }
}

async function start() {
  if (controller !== me && !(await act("control.take", { force: controller !== null }))) return;
  const s = await act("study.start", { study: fileStudy || $("e-study").value,
    participant: $("e-participant").value, resume: $("e-resume").checked });
  if (s) { current = s; session(s); }
}

const rpc = new Rpc(async () => {
  me = (await rpc.call("server.connection.identify", { client_name: "experimenter" })).client;
  const info = await rpc.call("server.info");
  showControl(info.controller, info.controller_name);
  const list = await rpc.call("study.list");
  $("e-study").replaceChildren(...list.studies.map((s) => new Option(`${s.name} (${s.source})`, s.name)));
  if (!list.sessions_possible) say("sessions need palpa serve --study-dir DIR");
  triggerLine = list.trigger_gpio;
  if (triggerLine) $("e-trigger").textContent = `trigger line: ${triggerLine}`;
  current = (await rpc.call("study.watch", { view: "experimenter" })).state;
  session(current);
}, (method, params) => {
  if (method === "notify_study") onStudy(params);
  else if (method === "notify_control") showControl(params.controller, params.controller_name);
}, (up) => {
  $("e-link").textContent = up ? "connected" : "disconnected, reconnecting";
  $("e-link").className = `state ${up ? "ok" : "bad"}`;
});

$("e-file").addEventListener("change", async () => {
  const f = $("e-file").files[0];
  fileStudy = null;
  if (!f) return;
  try { fileStudy = JSON.parse(await f.text()); say(`study document ${f.name} read: Start runs it`); }
  catch (e) { say(`${f.name}: ${e.message}`); }
});
$("e-study").addEventListener("change", () => { fileStudy = null; $("e-file").value = ""; });
$("e-take").addEventListener("click", () => act("control.take", { force: controller !== null }));
$("e-start").addEventListener("click", start);
$("e-stop").addEventListener("click", () => act("study.stop"));
