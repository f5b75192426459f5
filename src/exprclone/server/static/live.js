// exprclone live: camera frames to the server over a WebSocket, the portrait's frames back onto a canvas. The option
// controls are drawn from the server's description of its options (options.js): those a live message takes.
"use strict";

const $ = (selector) => document.querySelector(selector);
const WINDOW = 2; // frames in flight at most: the server keeps only the newest, so no backlog can build
const JPEG_QUALITY = 0.8;
const RATE_SPAN = 1000; // ms over which the frames per second are counted

let socket = null, stream = null, recorder = null;
let sequence = 0, inFlight = 0, dropped = 0, capturing = false, fresh = false;
const sentAt = new Map();
const shownAt = [], latencies = [];

function say(message) {
  $("#error").textContent = message ? message.replace(/^([a-z_]+):/, (_, field) => field.replace(/_/g, " ") + ":") : "";
  $("#error").hidden = !message;
}
function inform(message) { $("#message").textContent = message; }

// the controls, once drawn: the output sizes are those the live WebSocket renders
const drawn = Promise.all([drawOptions("json"), optionsAnswer]).then(([controls, answer]) => {
  for (const control of controls.filter((c) => c.option.value === "Framing" && c.tagName === "SELECT")) {
    for (const entry of [...control.options]) if (!answer.live.sizes.includes(Number(entry.value))) entry.remove();
  }
  for (const control of controls) control.addEventListener("change", sendChoices);
  $("#start").disabled = false;
  return controls;
}).catch((e) => { say(e.message); return []; });

async function setRunning(running) {
  $("#start").disabled = running;
  for (const id of ["#stop", "#neutral", "#record"]) $(id).disabled = !running;
  // the landmarker and the size are chosen at the start
  for (const control of (await drawn).filter((c) => c.option.name === "landmarker" || c.option.value === "Framing")) control.disabled = running;
}

$("#portrait").addEventListener("change", () => {
  const file = $("#portrait").files[0];
  if (file) $(".preview img").src = URL.createObjectURL(file);
});
$("#sample-portrait").addEventListener("click", async () => {
  const response = await fetch("/api/samples/portrait");
  const transfer = new DataTransfer();
  transfer.items.add(new File([await response.blob()], "portrait.jpg", { type: "image/jpeg" }));
  $("#portrait").files = transfer.files;
  $("#portrait").dispatchEvent(new Event("change"));
});

// one camera frame, at most the output size, as 4 bytes of sequence number and a JPEG
async function grab() {
  const video = $("#camera");
  const size = Number($("#size").value);
  const scale = Math.min(1, size / Math.max(video.videoWidth, video.videoHeight));
  const canvas = new OffscreenCanvas(Math.round(video.videoWidth * scale), Math.round(video.videoHeight * scale));
  canvas.getContext("2d").drawImage(video, 0, 0, canvas.width, canvas.height);
  const jpeg = await (await canvas.convertToBlob({ type: "image/jpeg", quality: JPEG_QUALITY })).arrayBuffer();
  const message = new Uint8Array(4 + jpeg.byteLength);
  new DataView(message.buffer).setUint32(0, sequence);
  message.set(new Uint8Array(jpeg), 4);
  return message;
}

async function sendMore() {
  if (capturing || !socket || socket.readyState !== WebSocket.OPEN) return;
  capturing = true;
  try {
    // only a new camera frame is sent: never the same one twice
    while (fresh && inFlight < WINDOW && socket && socket.readyState === WebSocket.OPEN && $("#camera").videoWidth) {
      fresh = false;
      const message = await grab();
      sentAt.set(sequence, performance.now());
      sequence += 1;
      inFlight += 1;
      socket.send(message);
    }
  } finally {
    capturing = false;
  }
}

function median(values) {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted.length ? sorted[Math.floor(sorted.length / 2)] : NaN;
}

async function show(buffer) {
  const number = new DataView(buffer).getUint32(0);
  const sent = sentAt.get(number);
  for (const older of [...sentAt.keys()]) {
    if (older < number) dropped += 1; // the server kept a newer frame instead
    if (older <= number) sentAt.delete(older);
  }
  inFlight = sentAt.size;
  sendMore(); // the next frame goes out while this one is drawn
  const bitmap = await createImageBitmap(new Blob([buffer.slice(4)], { type: "image/jpeg" }));
  const canvas = $("#output");
  canvas.getContext("2d").drawImage(bitmap, 0, 0, canvas.width, canvas.height);
  const now = performance.now();
  if (sent !== undefined) latencies.push(now - sent);
  while (latencies.length > 50) latencies.shift();
  shownAt.push(now);
}

setInterval(() => {
  const now = performance.now();
  while (shownAt.length && shownAt[0] < now - RATE_SPAN) shownAt.shift();
  $("#fps").textContent = String(Math.round((shownAt.length * 1000) / RATE_SPAN));
  $("#latency").textContent = latencies.length ? String(Math.round(median(latencies))) : "-";
  $("#dropped").textContent = String(dropped);
}, 250);

function onText(message) {
  if (message.type === "ready") {
    $("#output").width = message.width;
    $("#output").height = message.height;
    inform("Looking for your neutral face: keep still with your mouth closed for a second.");
    sendMore();
  } else if (message.type === "status") {
    if (!message.face) inform("No face seen: face the camera, in good light.");
    else if (!message.neutral) inform("Looking for your neutral face: keep still with your mouth closed for a second.");
    else inform("Following your face. Make faces!");
  } else if (message.type === "error") {
    say(message.error);
  }
}

async function start() {
  say("");
  const file = $("#portrait").files[0];
  if (!file) return say("portrait: choose a photo first");
  try {
    stream = await navigator.mediaDevices.getUserMedia({ video: { width: { ideal: 640 }, height: { ideal: 480 } }, audio: false });
  } catch (e) {
    return say(e.name === "NotAllowedError" ? "camera: the camera was refused; allow it in the browser and press Start again"
      : "camera: no camera found (" + e.name + ")");
  }
  $("#camera").srcObject = stream;
  sequence = 0; inFlight = 0; dropped = 0; sentAt.clear(); shownAt.length = 0; latencies.length = 0;
  const portrait = await file.arrayBuffer();  // read before the socket opens: no camera frame may go out before it
  const startChoices = optionValues(await drawn, true);
  socket = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/api/live`);
  socket.binaryType = "arraybuffer";
  socket.onopen = () => {
    socket.send(JSON.stringify({ type: "start", ...startChoices }));
    socket.send(portrait);
  };
  socket.onmessage = (event) => (typeof event.data === "string" ? onText(JSON.parse(event.data)) : show(event.data));
  socket.onclose = () => { if (socket) stop("The session ended."); };
  socket.onerror = () => say("live: the server cannot be reached");
  const camera = $("#camera");
  const onFrame = () => {
    fresh = true;
    sendMore();
    if (stream) camera.requestVideoFrameCallback(onFrame);
  };
  if (camera.requestVideoFrameCallback) camera.requestVideoFrameCallback(onFrame);
  else camera.onloadeddata = () => { const timer = setInterval(() => (stream ? ((fresh = true), sendMore()) : clearInterval(timer)), 40); };
  setRunning(true);
}

function stop(message) {
  const closing = socket;
  socket = null;
  if (closing && closing.readyState <= WebSocket.OPEN) closing.close();
  if (recorder && recorder.state === "recording") recorder.stop();
  if (stream) for (const track of stream.getTracks()) track.stop();
  stream = null;
  setRunning(false);
  inform(message || "Stopped.");
}

$("#start").addEventListener("click", start);
$("#stop").addEventListener("click", () => stop());
$("#neutral").addEventListener("click", () => socket && socket.send(JSON.stringify({ type: "neutral" })));
// every control's value, as the live protocol's options message takes them (a region's strength once moved)
async function sendChoices() {
  const values = optionValues(await drawn, true);
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify({ type: "options", ...values }));
}
$("#strengths-reset").addEventListener("click", async () => { resetSliders(await drawn); sendChoices(); });

$("#record").addEventListener("click", () => {
  if (recorder && recorder.state === "recording") return recorder.stop();
  const chunks = [];
  recorder = new MediaRecorder($("#output").captureStream(25), { mimeType: "video/webm" });
  recorder.ondataavailable = (event) => chunks.push(event.data);
  recorder.onstop = () => {
    $("#download-record").href = URL.createObjectURL(new Blob(chunks, { type: "video/webm" }));
    $("#download-record").hidden = false;
    $("#record").textContent = "Record";
  };
  recorder.start(500);
  $("#record").textContent = "Stop recording";
});
