// The participant's view: the question, the answer buttons, progress, "please wait" while the
// display settles, and the stop button. It joins the participant's channel alone, so its socket
// carries no condition, stimulus or correctness — the server never sends them here.
"use strict";

let state = { state: "idle", seq: 0 }, marked = [];

function show(section) {
  for (const id of ["p-wait", "p-ask", "p-feel", "p-break", "p-end"]) $(id).hidden = id !== section;
}

function fingerButtons(s) {
  const box = $("p-fingers");
  box.replaceChildren();
  marked = new Array(s.fingers).fill(false);
  const staircase = s.kind === "staircase";
  for (let f = 0; f < s.fingers; ++f) {
    if (staircase && !s.compared.includes(f)) continue;
    const b = document.createElement("button");
    b.textContent = `Finger ${f + 1}`;
    b.className = "p-finger";
    b.dataset.finger = f;
    b.addEventListener("click", () => {
      if (staircase) return answer(true, marked.map((_, k) => k === f));
      marked[f] = !marked[f];
      b.classList.toggle("marked", marked[f]);
      $("p-here").disabled = !marked.some((m) => m);
    });
    box.appendChild(b);
  }
  $("p-detection").hidden = staircase;
  $("p-here").disabled = true;
}

function render(s) {
  if (s.seq <= state.seq && s.seq !== 0) return;  // an older snapshot, overtaken
  state = s;
  $("p-progress").textContent = s.total ? `Trial ${Math.min(s.done + 1, s.total)} of ${s.total}` : "";
  $("p-message").textContent = "";
  if (s.state === "answer") {
    $("p-question").textContent = (s.practice ? "Practice: " : "") + s.question;
    fingerButtons(s);
    show("p-ask");
  } else if (s.state === "feel") {
    $("p-feel-text").textContent = `Finger ${s.finger + 1}: feel it.`;
    show("p-feel");
  } else if (s.state === "break") {
    show("p-break");
  } else if (s.state === "finished" || s.state === "stopped" || s.state === "idle") {
    $("p-end-text").textContent = s.state === "finished" ? "Thank you: the session is complete."
      : s.state === "stopped" ? "Stopped. Every finger is soft." : "Waiting for the session to start.";
    show("p-end");
  } else {
    show("p-wait");
  }
}

async function answer(tumour, fingers) {
  try {
    await rpc.call("study.answer", { trial: state.trial, tumour, fingers });
    show("p-wait");
  } catch (e) {
    $("p-message").textContent = e.message;
  }
}

async function send(method, params) {
  try {
    return await rpc.call(method, params);
  } catch (e) {
    $("p-message").textContent = e.message;
    return null;
  }
}

const rpc = new Rpc(async () => {
  await rpc.call("server.connection.identify", { client_name: "participant" });
  render((await rpc.call("study.watch", { view: "participant" })).state);
}, (method, params) => {
  if (method === "notify_study_participant") render(params);
}, (up) => { if (!up) $("p-message").textContent = "connection lost, reconnecting"; });

$("p-none").addEventListener("click", () => answer(false, marked.map(() => false)));
$("p-here").addEventListener("click", () => answer(true, marked.slice()));
$("p-next").addEventListener("click", () => send("study.next", { trial: state.trial }));
$("p-continue").addEventListener("click", () => send("study.next"));
$("p-stop").addEventListener("click", async () => {
  if (!(await send("study.stop"))) return;
  $("p-end-text").textContent = "Stopped. Every finger is soft.";
  show("p-end");
});
