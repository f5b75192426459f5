// exprclone's expression editor page: one photo prepared on the server (POST /api/editor), a slider for each control
// the server lists (GET /api/editor/controls), and each change rendered there (POST /api/editor/{id}/render): a
// preview while a slider moves, the full size when it is let go. No build step.
"use strict";

const $ = (selector) => document.querySelector(selector);
let editor = null; // the server's prepared photo: {id, render, ...}
let wanted = null; // the render asked for next: "preview" or "full"
let rendering = false;
let asked = 0; // when the newest slider value was set (performance.now())
let before = null; // the photo as it was, for the toggle
const urls = { preview: null, full: null };
window.previewTimes = []; // milliseconds from a slider's change to its preview on screen (benchmarks/sliders.py reads them)

function say(text) {
  $("#error").textContent = text;
  $("#error").hidden = !text;
}

const sliders = () => [...document.querySelectorAll("#controls input[type=range]")];

async function drawControls() {
  const { controls } = await (await call("/api/editor/controls")).json();
  for (const control of controls) {
    const id = `control-${control.name.replace(/_/g, "-")}`;
    const title = `${control.sentence} (${control.made}: ${control.source})`;
    const label = Object.assign(document.createElement("label"), { htmlFor: id, textContent: control.name.replace(/_/g, " "), title });
    const input = Object.assign(document.createElement("input"), { type: "range", id, name: control.name, min: 0, max: 1, step: 0.05, value: 0 });
    const output = Object.assign(document.createElement("output"), { htmlFor: id, textContent: "0" });
    input.addEventListener("input", () => { output.textContent = input.value; asked = performance.now(); refresh("preview"); });
    input.addEventListener("change", () => refresh("full"));
    $("#reset").before(label, input, output);
  }
}

function shown(src) {
  const img = $("#result");
  if ($("#toggle").getAttribute("aria-pressed") === "true") return Promise.resolve();
  return new Promise((resolve) => { img.onload = resolve; img.onerror = resolve; img.src = src; });
}

// the photo with the sliders' values, at "preview" or "full" size
async function render(size) {
  const form = new FormData();
  for (const input of sliders()) if (Number(input.value) > 0) form.append(input.name, input.value);
  const values = Object.fromEntries(form.entries());
  const since = asked;
  const blob = await (await call(`${editor.render}?preview=${size === "preview"}`, { method: "POST", body: form })).blob();
  if (urls[size]) URL.revokeObjectURL(urls[size]);
  urls[size] = URL.createObjectURL(blob);
  await shown(urls[size]);
  if (size === "preview") window.previewTimes.push(performance.now() - since);
  else Object.assign($("#download"), { href: urls.full, hidden: false });
  $("#result").dataset.rendered = JSON.stringify({ size, ...values });
}

// only the newest render asked for waits its turn
async function refresh(size) {
  if (!editor) return;
  wanted = wanted === "full" && size === "preview" ? "full" : size;
  if (rendering) return;
  rendering = true;
  try {
    while (wanted && editor) {
      const next = wanted;
      wanted = null;
      await render(next);
    }
  } catch (e) {
    say(e.status === 404 ? "the prepared photo has expired: choose it again" : e.message);
  } finally {
    rendering = false;
  }
}

function forget() {
  if (editor) fetch(`/api/editor/${editor.id}`, { method: "DELETE", keepalive: true }).catch(() => {});
  editor = null;
}
window.addEventListener("pagehide", forget);

async function open(file) {
  say("");
  forget();
  $("#message").textContent = "Preparing the photo...";
  const form = new FormData();
  form.append("photo", file);
  try {
    editor = await (await call("/api/editor", { method: "POST", body: form })).json();
    if (before) URL.revokeObjectURL(before);
    before = URL.createObjectURL(file);
    $("#toggle").disabled = false;
    $("#message").textContent = "";
    await refresh("full");
  } catch (e) {
    $("#message").textContent = "";
    say(e.message);
  }
}

$("#photo").addEventListener("change", () => { if ($("#photo").files[0]) open($("#photo").files[0]); });
$("#sample").addEventListener("click", async () => {
  try {
    open(await (await call("/api/samples/target_neutral")).blob());
  } catch (e) {
    say(e.message);
  }
});
$("#reset").addEventListener("click", () => {
  for (const input of sliders()) { input.value = 0; input.nextElementSibling.textContent = "0"; }
  refresh("full");
});
$("#toggle").addEventListener("click", () => {
  const showing = $("#toggle").getAttribute("aria-pressed") !== "true";
  $("#toggle").setAttribute("aria-pressed", String(showing));
  $("#toggle").textContent = showing ? "Show after" : "Show before";
  $("#result").src = showing ? before : urls.full || urls.preview;
});
drawControls().catch((e) => say(e.message));
