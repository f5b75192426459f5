// The study's page: an anonymous participant rates each set's results 1 to 5, set by set, and may come back. No build step.
"use strict";

const $ = (selector) => document.querySelector(selector);
// where the browser keeps the participant's id, to come back to the same ratings and the same order
const KEY = "exprclone-study-participant";
const REQUEST_TIMEOUT = 30000; // ms: a request never hangs the page
const SCORES = [1, 2, 3, 4, 5];
const STEPS = ["#loading", "#about", "#set", "#done"];

let state = null; // the participant's state, as the server gives it
let current = -1; // the set on screen

function say(message) {
  $("#error").textContent = message || "";
  $("#error").hidden = !message;
}

// the JSON of an answer (call.js: the server's {"error"} as an Error with the status)
const json = async (url, options = {}) => (await call(url, options, REQUEST_TIMEOUT)).json();

const put = (url, body) => json(url, { method: "PUT", headers: { "content-type": "application/json" }, body: JSON.stringify(body) });

// the participant this browser is, or a new one if it is none yet (or the study no longer knows it)
async function participant() {
  const known = localStorage.getItem(KEY);
  if (known) {
    try {
      return await json(`/api/participants/${encodeURIComponent(known)}`);
    } catch (e) {
      if (e.status !== 404 && e.status !== 400) throw e;
    }
  }
  const made = await json("/api/participants", { method: "POST" });
  localStorage.setItem(KEY, made.id);
  return json(`/api/participants/${made.id}`);
}

function show(step) {
  for (const id of STEPS) $(id).hidden = id !== step;
  const title = $(step).querySelector("[tabindex='-1']");
  if (title) title.focus();
}

// the first set not rated yet, after the questions about the participant
function next() {
  current = state.sets.findIndex((_, k) => !(String(k) in state.ratings));
  if (state.about === null) show("#about");
  else if (current < 0) show("#done");
  else render(current);
}

const letter = (k) => (k < 26 ? String.fromCharCode(65 + k) : String(k + 1));

function item(entry, k) {
  const box = document.createElement("fieldset");
  box.className = "item";
  box.dataset.item = entry.id;
  const legend = document.createElement("legend");
  legend.textContent = `Result ${letter(k)}`;
  const image = document.createElement("img");
  image.src = entry.image;
  image.alt = `Result ${letter(k)}`;
  const scale = document.createElement("div");
  scale.className = "scale";
  for (const score of SCORES) {
    const label = document.createElement("label");
    const input = document.createElement("input");
    Object.assign(input, { type: "radio", name: `score-${entry.id}`, value: String(score) });
    input.setAttribute("aria-describedby", "scale-hint");
    label.append(input, String(score));
    scale.append(label);
  }
  box.append(legend, image, scale);
  return box;
}

function render(k) {
  const set = state.sets[k];
  $("#set-title").textContent = `Set ${k + 1} of ${state.sets.length}`;
  $("#source-neutral").src = set.photos.source_neutral;
  $("#source-expression").src = set.photos.source_expression;
  $("#target-neutral").src = set.photos.target_neutral;
  $("#items").replaceChildren(...set.items.map(item));
  $("#progress").textContent = `${Object.keys(state.ratings).length} of ${state.sets.length} sets rated`;
  show("#set");
}

async function saving(button, work) {
  button.disabled = true;
  try {
    state = await work();
    say("");
    next();
  } catch (e) {
    say(e.message);
  } finally {
    button.disabled = false;
  }
}

$("#about").addEventListener("submit", (event) => {
  event.preventDefault();
  const text = $("#age").value.trim();
  const age = text === "" ? null : Number(text);
  if (age !== null && !(Number.isInteger(age) && age >= 1 && age <= 120)) {
    say("Age: a whole number of years from 1 to 120, or leave it empty.");
    $("#age").focus();
    return;
  }
  const about = { age, gender: $("#gender").value || null };
  saving($("#begin"), () => put(`/api/participants/${state.participant}/about`, about));
});

$("#set").addEventListener("submit", (event) => {
  event.preventDefault();
  const ratings = {};
  const missing = [];
  for (const box of document.querySelectorAll("#items [data-item]")) {
    const checked = box.querySelector("input:checked");
    box.classList.toggle("missing", !checked);
    if (checked) ratings[box.dataset.item] = Number(checked.value);
    else missing.push(box);
  }
  if (missing.length) {
    const names = missing.map((box) => box.querySelector("legend").textContent).join(", ");
    say(`Rate every result before you go on: ${names} ${missing.length > 1 ? "have" : "has"} no score yet.`);
    missing[0].querySelector("input").focus();
    return;
  }
  saving($("#submit"), () => put(`/api/participants/${state.participant}/sets/${current}`, { ratings }));
});

participant().then(
  (found) => { state = found; next(); },
  (e) => { say(`The study cannot start: ${e.message}`); $("#loading").hidden = true; },
);
