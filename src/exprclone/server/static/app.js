// exprclone's page: a photo and an expression (built-in, or two photos of someone), the strengths' sliders, the result
// large with a full-size view; the paper's choices under "Advanced"; video jobs. No build step. The option controls are
// drawn from the server's description of its options (options.js), and sent by their keys.
"use strict";

const $ = (selector) => document.querySelector(selector);
const POLL_EVERY = 500; // ms between two looks at a video job
const THUMBNAIL = 256; // pixels of a face's thumbnail canvas (shown at 8rem)
const FACE_MARGIN = 0.4; // a face's thumbnail shows its box grown by this share of its width on every side

// The server names inputs by their form field ("target_neutral: no face found"); the page by their label.
// "target_neutral: no face found" -> "target neutral: no face found"
const readable = (message) => message.replace(/^([a-z_]+):/, (_, field) => field.replace(/_/g, " ") + ":");

function say(message) {
  const box = $("#error");
  box.textContent = message ? readable(message) : "";
  box.hidden = !message;
}

// the clone's role warnings (photos that look swapped, or of two people, or one photo given twice), beside its result
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

function zoneOf(field) {
  return document.querySelector(`.zone[data-field="${field}"]`);
}

// what is wrong with a zone's photo, in the zone itself, as soon as it is chosen ("" when nothing is)
function problem(zone, message) {
  const box = zone.querySelector(".problem");
  zone.problem = message;
  if (!box) return;
  box.textContent = message;
  box.hidden = !message;
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
  for (const face of zoneOf("target_neutral").faces.faces) {
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
zoneOf("target_neutral").querySelector("canvas").addEventListener("click", (event) => {
  const zone = zoneOf("target_neutral");
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
  const zone = zoneOf("target_neutral");
  if (!zone.faces) return null;
  const boxes = [...$("#faces").querySelectorAll("input")];
  const taken = boxes.filter((b) => b.checked).map((b) => b.value);
  if (!taken.length) throw new Error("target_neutral: choose at least one face");
  return boxes.every((b) => b.checked || b.disabled) ? "all" : taken.join(",");
}

// a photo chosen: shown, and looked at by the server at once (its landmarks; a target's faces), so that what is wrong
// with it (no face, too small, not an image) is said in its zone before Clone; only the newest choice of a zone counts
async function preview(zone) {
  const file = zone.querySelector("input").files[0];
  const media = zone.querySelector("img, video");
  const chosen = (zone.chosen = {});
  zone.found = null;
  problem(zone, "");
  if (zone.dataset.field === "target_neutral") clearFaces(zone);
  if (!file) return;
  media.src = URL.createObjectURL(file);
  if (media.tagName !== "IMG") return;
  await new Promise((resolve) => { media.onload = resolve; media.onerror = resolve; }); // (the server says what a bad file is)
  try {
    const form = new FormData();
    form.append("photo", file);
    await addLandmarker(form);
    const found = await (await call("/api/landmarks", { method: "POST", body: form })).json();
    if (zone.chosen !== chosen) return;
    zone.found = found;
    if (zone.dataset.field === "target_neutral") await findFaces(zone, file);
  } catch (e) {
    if (zone.chosen === chosen) problem(zone, e.message.replace(/^photo: /, ""));
  }
  if (zone.chosen === chosen && media.naturalWidth) drawLandmarks(zone, zone.found);
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
$("#samples").addEventListener("click", () => loadSamples(["target_neutral", "source_neutral", "source_expression"]));
$("#video-samples").addEventListener("click", () => loadSamples(["portrait", "driving_video"]));

// --- the expression: a built-in one, or the source's two photos ------------------------------
const SOURCES = ["source_neutral", "source_expression"];

function builtIn() {
  return $("#source-builtin").checked;
}
function showSourceKind() {
  $("#expression").disabled = !builtIn();
  $("#source-zones").hidden = builtIn();
  for (const field of SOURCES) zoneOf(field).hidden = builtIn();
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

// the photos a clone needs, each chosen and with nothing wrong said of it (else an Error naming it)
function photosAsked(fields) {
  for (const field of fields) {
    if (!fileOf(field)) throw new Error(`${field}: choose a photo`);
    if (zoneOf(field).problem) throw new Error(`${field}: ${zoneOf(field).problem}`);
  }
  return fields;
}

async function cloneForm(withMethod) {
  const form = new FormData();
  if (builtIn()) form.append("expression", $("#expression").value);
  for (const field of photosAsked(builtIn() ? ["target_neutral"] : [...SOURCES, "target_neutral"])) form.append(field, fileOf(field));
  const faces = facesAsked();
  if (faces) form.append("faces", faces);
  await addOptions(form, ["Options"]);
  if (!withMethod) form.delete("method"); // every method is on the sheet
  if (fileOf("global_landmarks")) form.append("global_landmarks", fileOf("global_landmarks"));
  return form;
}

// --- clone: a prepared clone (an edit) on the server, rendered again as the sliders move -------------------------------
let shown = { result: null, full: null, before: null, faces: [] };
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

function showingBefore() {
  return $("#toggle").getAttribute("aria-pressed") === "true";
}

// the result on screen (unless "before" is shown: then the toggle shows it), once the browser has decoded it
function showImage(src) {
  const img = $("#result");
  if (showingBefore()) return Promise.resolve();
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
    shown.full = shown.result = `data:image/png;base64,${record.png}`;
    delete record.png;
    await showImage(shown.result);
    $("#result-caption").textContent = await caption(record);
    $("#download-png").href = shown.result;
    $("#download-json").href = URL.createObjectURL(new Blob([JSON.stringify(record, null, 1)], { type: "application/json" }));
    await showFaces(record.faces.filter((face) => !face.problem));
    if ($("#viewer").open) showInViewer();
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

function showBefore(before) {
  $("#toggle").setAttribute("aria-pressed", String(before));
  $("#toggle").textContent = before ? "Show after" : "Show before";
  $("#result").src = before ? shown.before : shown.result;
  showInViewer();
}

$("#clone").addEventListener("click", async () => {
  say("");
  warn([]);
  busy(true);
  try {
    const form = await cloneForm(true);
    forget();
    edit = await (await call("/api/edits", { method: "POST", body: form })).json();
    if (shown.before) URL.revokeObjectURL(shown.before);
    shown.before = URL.createObjectURL(fileOf("target_neutral"));
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

$("#toggle").addEventListener("click", () => showBefore(!showingBefore()));
$("#viewer-toggle").addEventListener("click", () => showBefore(!showingBefore()));

// --- the full-size view: the result (or the photo before) at its own pixels, in a dialog that scrolls ---------------
function showInViewer() {
  const image = $("#viewer-image");
  const source = showingBefore() ? shown.before : shown.full;
  if (source && image.getAttribute("src") !== source) image.src = source;
  $("#viewer-toggle").setAttribute("aria-pressed", String(showingBefore()));
  $("#viewer-toggle").textContent = showingBefore() ? "Show after" : "Show before";
}

// open the full-size view; with a face (a group photo's), scrolled to it
async function openViewer(face = null) {
  showInViewer();
  const image = $("#viewer-image");
  if (!image.complete || !image.naturalWidth) await new Promise((resolve) => { image.onload = resolve; image.onerror = resolve; });
  $("#viewer-title").textContent = `Full size: ${image.naturalWidth} × ${image.naturalHeight} pixels${face ? `, face ${face.number}` : ""}`;
  $("#viewer").showModal();
  const area = $("#viewer .canvas");
  const [left, top, right, bottom] = face ? face.box : [0, 0, image.naturalWidth, image.naturalHeight];
  area.scrollLeft = image.offsetLeft + (left + right) / 2 - area.clientWidth / 2;
  area.scrollTop = image.offsetTop + (top + bottom) / 2 - area.clientHeight / 2;
}
$("#full-size").addEventListener("click", () => openViewer());
$("#result-open").addEventListener("click", () => openViewer());
$("#viewer-close").addEventListener("click", () => $("#viewer").close());

// a group photo's cloned faces, each a thumbnail of the result that opens the full-size view on it
async function showFaces(faces) {
  const list = $("#result-faces .thumbnails");
  list.replaceChildren();
  $("#result-faces").hidden = faces.length < 2;
  if (faces.length < 2) return;
  const image = new Image();
  await new Promise((resolve) => { image.onload = resolve; image.onerror = resolve; image.src = shown.full; });
  for (const face of faces) {
    const [left, top, right, bottom] = face.box;
    const side = Math.max(right - left, bottom - top) * (1 + 2 * FACE_MARGIN);
    const canvas = Object.assign(document.createElement("canvas"), { width: THUMBNAIL, height: THUMBNAIL });
    canvas.getContext("2d").drawImage(image, (left + right - side) / 2, (top + bottom - side) / 2, side, side, 0, 0, THUMBNAIL, THUMBNAIL);
    const button = Object.assign(document.createElement("button"), { type: "button", id: `result-face-${face.number}` });
    button.append(canvas, `face ${face.number}`);
    button.addEventListener("click", () => openViewer(face));
    list.append(button);
  }
}

// --- the paper's comparison sheets (under "Advanced") ----------------------------------------------------------------
// what each sheet but Fig. 11's shows (Fig. 11's caption says whether the default's row is drawn)
const CAPTIONS = {
  16: "Fig. 16 of the paper on these photos: global warping with the ERI, Song et al.'s method, the elastic model with the ERI and E+MD, and E+MD against Song et al.'s.",
  17: "Fig. 17 of the paper on these photos: Song et al.'s method, the elastic model with the ERI and E+MD, all on Song et al.'s global warp.",
  19: "Figs. 19-21 of the paper on these photos: the elastic model on the result of another global warp, and the DB metric over λk.",
};
$("#compare").addEventListener("click", async () => {
  say("");
  busy(true);
  try {
    const figure = $("#figure").value;
    const form = await cloneForm(false);
    if (figure === "17") form.delete("global_warp"); // (Fig. 17 is drawn on Song et al.'s warp alone)
    form.append("figure", figure);
    const url = URL.createObjectURL(await (await call("/api/compare", { method: "POST", body: form })).blob());
    $("#sheet-caption").textContent = CAPTIONS[figure]
      || "Figs. 11-13 of the paper on these photos by the paper's stages, and the DB metric's choice of λk explained;"
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
      if (zoneOf(field).problem) throw new Error(`${field}: ${zoneOf(field).problem}`);
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
