// exprclone's page: drop zones with previews and landmarks, clone, compare, video jobs. No build step. The option
// controls are drawn from the server's description of its options (options.js), and sent by their keys.
"use strict";

const $ = (selector) => document.querySelector(selector);
const POLL_EVERY = 500; // ms between two looks at a video job

// The server names inputs by their form field ("target_neutral: no face found"); the page by their label.
// "target_neutral: no face found" -> "target neutral: no face found"
const readable = (message) => message.replace(/^([a-z_]+):/, (_, field) => field.replace(/_/g, " ") + ":");

function say(message) {
  const box = $("#error");
  box.textContent = message ? readable(message) : "";
  box.hidden = !message;
}

// the clone's role warnings (photos that look swapped, or of two people), beside its result
function warn(messages) {
  const box = $("#warning");
  box.textContent = messages.map(readable).join(" ");
  box.hidden = messages.length === 0;
}

function busy(on) {
  $("#busy").hidden = !on;
  for (const id of ["#clone", "#compare", "#video-start"]) $(id).disabled = on;
}

function fileOf(field) {
  return document.getElementById(field).files[0];
}

// --- drop zones, previews, landmarks ----------------------------------------------------
function drawLandmarks(zone, found) {
  const img = zone.querySelector("img");
  const canvas = zone.querySelector("canvas");
  canvas.width = img.clientWidth;
  canvas.height = img.clientHeight;
  const context = canvas.getContext("2d");
  context.clearRect(0, 0, canvas.width, canvas.height);
  if (zone.faces) drawFaces(context, canvas.width / zone.faces.width);
  if (!found || !$("#show-landmarks").checked || zone.faces) return;
  const scale = canvas.width / found.width;
  context.fillStyle = "#00e676";
  for (const [x, y] of found.landmarks) {
    context.beginPath();
    context.arc(x * scale, y * scale, 2, 0, 2 * Math.PI);
    context.fill();
  }
}

// --- the faces of a group photo (POST /api/faces): outlined and numbered on the target's preview; a click on one,
// or its checkbox, leaves it out or takes it back (the clone's "faces" field) --------------------------------------
function faceBox(number) {
  return document.getElementById(`face-${number}`);
}

function drawFaces(context, scale) {
  context.lineWidth = 2;
  context.font = "bold 13px sans-serif";
  for (const face of $(".zone[data-field=target_neutral]").faces.faces) {
    const [left, top, right, bottom] = face.box.map((v) => v * scale);
    const taken = faceBox(face.number).checked;
    context.strokeStyle = context.fillStyle = face.problem ? "#e53935" : taken ? "#00e676" : "#9e9e9e";
    context.setLineDash(taken ? [] : [4, 3]);
    context.strokeRect(left, top, right - left, bottom - top);
    context.fillText(String(face.number), left + 2, Math.max(12, top - 3));
  }
  context.setLineDash([]);
}

function clearFaces(zone) {
  zone.faces = null;
  $("#faces").hidden = true;
  zone.querySelector("canvas").classList.remove("faces-shown");
  for (const label of $("#faces").querySelectorAll("label")) label.remove();
}

async function findFaces(zone, file) {
  const list = $("#faces");
  const canvas = zone.querySelector("canvas");
  const form = new FormData();
  form.append("photo", file);
  await addLandmarker(form);
  const found = await (await call("/api/faces", { method: "POST", body: form })).json();
  if (found.faces.length < 2) return;
  for (const face of found.faces) {
    const label = document.createElement("label");
    const box = Object.assign(document.createElement("input"), { type: "checkbox", id: `face-${face.number}`, value: face.number });
    box.checked = !face.problem;
    box.disabled = Boolean(face.problem);
    box.addEventListener("change", () => drawLandmarks(zone, zone.found));
    label.append(box, ` ${face.number}${face.problem ? ` (left as it is: ${face.problem})` : ""}`);
    list.append(label);
  }
  zone.faces = found;
  list.hidden = false;
  canvas.classList.add("faces-shown");
}

// a click on the target's preview toggles the face under it
$(".zone[data-field=target_neutral] canvas").addEventListener("click", (event) => {
  const zone = $(".zone[data-field=target_neutral]");
  if (!zone.faces) return;
  const canvas = event.currentTarget;
  const scale = zone.faces.width / canvas.clientWidth;
  const [x, y] = [event.offsetX * scale, event.offsetY * scale];
  const face = zone.faces.faces.find(({ box }) => box[0] <= x && x <= box[2] && box[1] <= y && y <= box[3]);
  const box = face && faceBox(face.number);
  if (!box || box.disabled) return;
  box.checked = !box.checked;
  box.dispatchEvent(new Event("change"));
});

// the faces field: the numbers of the faces taken, "all" when no face is left out, nothing for a photo of one face
function facesAsked() {
  const zone = $(".zone[data-field=target_neutral]");
  if (!zone.faces) return null;
  const boxes = [...$("#faces").querySelectorAll("input")];
  const taken = boxes.filter((b) => b.checked).map((b) => b.value);
  if (!taken.length) throw new Error("target_neutral: choose at least one face");
  return boxes.every((b) => b.checked || b.disabled) ? "all" : taken.join(",");
}

async function preview(zone) {
  const input = zone.querySelector("input");
  const file = input.files[0];
  const media = zone.querySelector("img, video");
  zone.found = null;
  if (zone.dataset.field === "target_neutral") clearFaces(zone);
  if (!file) return;
  media.src = URL.createObjectURL(file);
  if (media.tagName !== "IMG") return;
  await new Promise((resolve) => { media.onload = resolve; });
  try {
    const form = new FormData();
    form.append("photo", file);
    await addLandmarker(form);
    zone.found = await (await call("/api/landmarks", { method: "POST", body: form })).json();
    if (zone.dataset.field === "target_neutral") await findFaces(zone, file);
    say("");
  } catch (e) {
    say(e.message.replace(/^photo:/, zone.dataset.field + ":"));
  }
  drawLandmarks(zone, zone.found);
}

function setFile(input, file) {
  const transfer = new DataTransfer();
  transfer.items.add(file);
  input.files = transfer.files;
  input.dispatchEvent(new Event("change"));
}

for (const zone of document.querySelectorAll(".zone")) {
  const input = zone.querySelector("input");
  input.addEventListener("change", () => preview(zone));
  zone.addEventListener("dragover", (event) => { event.preventDefault(); zone.classList.add("over"); });
  zone.addEventListener("dragleave", () => zone.classList.remove("over"));
  zone.addEventListener("drop", (event) => {
    event.preventDefault();
    zone.classList.remove("over");
    if (event.dataTransfer.files.length) setFile(input, event.dataTransfer.files[0]);
  });
}
$("#show-landmarks").addEventListener("change", () => {
  for (const zone of document.querySelectorAll(".zone")) if (zone.querySelector("canvas")) drawLandmarks(zone, zone.found);
});

async function loadSamples(fields) {
  try {
    for (const field of fields) {
      const blob = await (await call(`/api/samples/${field}`)).blob();
      const name = field === "driving_video" ? "sample.mp4" : `${field}.jpg`;
      setFile(document.getElementById(field), new File([blob], name, { type: blob.type }));
    }
  } catch (e) {
    say(e.message);
  }
}
$("#samples").addEventListener("click", () => loadSamples(["source_neutral", "source_expression", "target_neutral"]));
$("#video-samples").addEventListener("click", () => loadSamples(["portrait", "driving_video"]));

// --- a built-in expression instead of the source's two photos ------------------------------
const SOURCES = ["source_neutral", "source_expression"];

function builtIn() {
  return $("#source-builtin").checked;
}
function showSourceKind() {
  $("#expression").disabled = !builtIn();
  for (const field of SOURCES) document.querySelector(`.zone[data-field="${field}"]`).hidden = builtIn();
}
for (const radio of document.querySelectorAll('input[name="source-kind"]')) radio.addEventListener("change", showSourceKind);

async function loadExpressions() {
  try {
    const listed = (await (await call("/api/expressions")).json()).expressions;
    for (const { name, description } of listed) {
      const option = new Option(name, name);
      option.title = description;
      $("#expression").append(option);
    }
  } catch (e) {
    say(e.message);
  }
}
loadExpressions();
showSourceKind();

// --- options: the controls drawn from the server's description (options.js) -------------------------------------------
const drawn = drawOptions("form").then((controls) => {
  for (const id of ["#clone", "#compare", "#video-start"]) $(id).disabled = false;
  const landmarker = controls.find((c) => c.option.name === "landmarker");
  landmarker?.addEventListener("change", () => {
    for (const zone of document.querySelectorAll(".zone")) if (zone.querySelector("canvas")) preview(zone);
  });
  for (const control of controls.filter((c) => c.type === "range")) {
    control.addEventListener("input", () => { asked = performance.now(); refresh("preview"); });
    control.addEventListener("change", () => refresh("full"));
  }
  return controls;
}).catch((e) => { say(e.message); return []; });

$("#strengths-reset").addEventListener("click", async () => { resetSliders(await drawn); refresh("full"); });

// the landmarker chosen, for a photo's landmarks and faces
async function addLandmarker(form) {
  for (const [key, value] of Object.entries(optionValues((await drawn).filter((c) => c.option.name === "landmarker")))) form.append(key, value);
}

// the options of the controls of `values` ("Options": a clone's; "Driving", "Framing": a video's) as form fields; the
// sliders alone for a render of the prepared clone
async function addOptions(form, values, slidersOnly = false) {
  const chosen = (await drawn).filter((c) => values.includes(c.option.value) && (!slidersOnly || c.type === "range"));
  for (const [key, value] of Object.entries(optionValues(chosen))) form.append(key, value);
}

async function cloneForm(withMethod) {
  const form = new FormData();
  if (builtIn()) form.append("expression", $("#expression").value);
  for (const field of builtIn() ? ["target_neutral"] : [...SOURCES, "target_neutral"]) {
    const file = fileOf(field);
    if (!file) throw new Error(`${field}: choose a photo`);
    form.append(field, file);
  }
  const faces = facesAsked();
  if (faces) form.append("faces", faces);
  await addOptions(form, ["Options"]);
  if (!withMethod) form.delete("method"); // every method is on the sheet
  if (fileOf("global_landmarks")) form.append("global_landmarks", fileOf("global_landmarks"));
  return form;
}

// --- clone: a prepared clone (an edit) on the server, rendered again as the sliders move -------------------------------
let shown = { result: null, before: null };
let edit = null; // the server's prepared clone: {id, render, ...} (POST /api/edits)
let wanted = null; // the render asked for next: "preview" or "full"
let rendering = false;
let asked = 0; // when the newest slider value was set (performance.now())
window.previewTimes = []; // milliseconds from a slider's change to its preview on screen (benchmarks/sliders.py reads them)

function forget() {
  if (edit) fetch(`/api/edits/${edit.id}`, { method: "DELETE", keepalive: true }).catch(() => {});
  edit = null;
}
window.addEventListener("pagehide", forget);

async function caption(record) {
  const lambda = record.lambda_k === null ? "" : `, λk = ${record.lambda_k}`;
  const how = optionsSaid(record, await describedOptions);
  const source = builtIn() ? `, expression ${$("#expression").value}` : "";
  const cloned = record.faces.filter((face) => !face.problem).map((face) => face.number);
  const faces = record.faces.length ? `, faces ${cloned.join(",") || "none"} of ${record.faces.length}` : "";
  return `${record.method}${source}${lambda}${faces}${how.map((h) => `, ${h}`).join("")}. `;
}

// the result on screen (unless "before" is shown: then the toggle shows it), once the browser has decoded it
function showImage(src) {
  const img = $("#result");
  if ($("#toggle").getAttribute("aria-pressed") === "true") return Promise.resolve();
  return new Promise((resolve) => { img.onload = resolve; img.onerror = resolve; img.src = src; });
}

// render the edit at "preview" or "full" size with the sliders' values; only the newest request waits its turn
async function renderEdit(size) {
  const form = new FormData();
  await addOptions(form, ["Options"], true);
  const values = Object.fromEntries(form.entries());
  const since = asked;
  if (size === "preview") {
    const blob = await (await call(`${edit.render}?preview=true`, { method: "POST", body: form })).blob();
    if (shown.preview) URL.revokeObjectURL(shown.preview);
    shown.preview = shown.result = URL.createObjectURL(blob);
    await showImage(shown.result);
    window.previewTimes.push(performance.now() - since);
  } else {
    const record = await (await call(`${edit.render}?preview=false&format=json`, { method: "POST", body: form })).json();
    shown.result = `data:image/png;base64,${record.png}`;
    delete record.png;
    await showImage(shown.result);
    $("#result-caption").textContent = await caption(record);
    $("#download-png").href = shown.result;
    $("#download-json").href = URL.createObjectURL(new Blob([JSON.stringify(record, null, 1)], { type: "application/json" }));
  }
  $("#result").dataset.rendered = JSON.stringify({ size, ...values });
}

async function refresh(size) {
  if (!edit) return;
  wanted = wanted === "full" && size === "preview" ? "full" : size;
  if (rendering) return;
  rendering = true;
  try {
    while (wanted && edit) {
      const next = wanted;
      wanted = null;
      await renderEdit(next);
    }
  } catch (e) {
    say(e.status === 404 ? "the prepared clone has expired: press Clone again" : e.message);
  } finally {
    rendering = false;
  }
}

$("#clone").addEventListener("click", async () => {
  say("");
  warn([]);
  busy(true);
  try {
    forget();
    edit = await (await call("/api/edits", { method: "POST", body: await cloneForm(true) })).json();
    shown.before = URL.createObjectURL(fileOf("target_neutral"));
    $("#before").src = shown.before;
    $("#toggle").setAttribute("aria-pressed", "false");
    $("#toggle").textContent = "Show before";
    await renderEdit("full");
    $("#result-box").hidden = false;
    warn(edit.warnings);
  } catch (e) {
    say(e.message);
  } finally {
    busy(false);
  }
});

$("#toggle").addEventListener("click", () => {
  const before = $("#toggle").getAttribute("aria-pressed") !== "true";
  $("#result").src = before ? shown.before : shown.result;
  $("#toggle").setAttribute("aria-pressed", String(before));
  $("#toggle").textContent = before ? "Show after" : "Show before";
});

$("#compare").addEventListener("click", async () => {
  say("");
  busy(true);
  try {
    const form = await cloneForm(false);
    form.append("figure", $("#figure").value);
    const url = URL.createObjectURL(await (await call("/api/compare", { method: "POST", body: form })).blob());
    $("#sheet-caption").textContent = $("#figure").value === "19"
      ? "Figs. 19-21 of the paper on these photos: the elastic model on the result of another global warp, and the DB metric over λk."
      : "Figs. 11-13 of the paper on these photos by the paper's stages, and the DB metric's choice of λk explained;"
        + ($("#retarget") && $("#retarget").checked ? " last row: this project's default (the target's own smile)." : "");
    $("#sheet").src = url;
    $("#download-sheet").href = url;
    $("#sheet-box").hidden = false;
  } catch (e) {
    say(e.message);
  } finally {
    busy(false);
  }
});

// --- video jobs ---------------------------------------------------------------------------
function sleep(ms) { return new Promise((resolve) => setTimeout(resolve, ms)); }

$("#video-start").addEventListener("click", async () => {
  say("");
  busy(true);
  const progress = $("#video-progress");
  try {
    const form = new FormData();
    for (const field of ["portrait", "driving_video"]) {
      if (!fileOf(field)) throw new Error(`${field}: choose a file`);
      form.append(field, fileOf(field));
    }
    await addOptions(form, ["Options", "Driving", "Framing"]);
    const job = await (await call("/api/video", { method: "POST", body: form })).json();
    progress.hidden = false;
    progress.value = 0;
    for (;;) {
      const state = await (await call(job.status)).json();
      progress.value = state.progress;
      $("#video-state").textContent = `${state.state} ${Math.round(100 * state.progress)}%`;
      if (state.state === "failed") throw new Error(state.error);
      if (state.state === "done") break;
      await sleep(POLL_EVERY);
    }
    const url = URL.createObjectURL(await (await call(job.result)).blob());
    $("#video-result").src = url;
    $("#download-video").href = url;
    $("#video-box").hidden = false;
  } catch (e) {
    say(e.message);
    $("#video-state").textContent = "";
  } finally {
    busy(false);
  }
});
