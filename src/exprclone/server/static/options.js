// The option controls of exprclone's pages (the clone page and live), drawn from the server's own description of its
// options (GET /api/options: each option's kind, default, bounds, choices and words), so that a page offers what the
// server takes, by the same names, and never lists them itself. No build step: a classic script, loaded before the
// page's own.
"use strict";

// the server's answer, asked for once
const optionsAnswer = fetch("/api/options").then((response) => {
  if (!response.ok) throw new Error(`options: the server answered ${response.status}`);
  return response.json();
});

// the options by key (a form field's name), once the answer is in
const describedOptions = optionsAnswer.then((answer) => Object.fromEntries(answer.options.map((option) => [option.key, option])));

// what an element's id is made of: its fieldset's prefix and the option's key with dashes ("strength_mouth" -> "strength-mouth")
const controlId = (prefix, option) => prefix + option.key.replace(/_/g, "-");

function label(option, id) {
  return Object.assign(document.createElement("label"), { htmlFor: id, textContent: option.page.label, title: option.page.sentence });
}

// a menu of the values the page offers, the default chosen (or a first entry that sends nothing, when absent is not the default)
function menu(option, id) {
  const select = Object.assign(document.createElement("select"), { id, name: option.key, title: option.page.sentence });
  if (option.page.unset !== null) select.append(new Option(option.page.unset, "", true, true));
  for (const choice of option.page.choices) {
    const entry = new Option(choice.label, choice.value, false, option.page.unset === null && choice.value === String(option.default));
    entry.title = choice.sentence;
    select.append(entry);
  }
  return select;
}

function checkbox(option, id) {
  return Object.assign(document.createElement("input"), { type: "checkbox", id, name: option.key, checked: option.default === true });
}

// a slider over the option's range; one that follows another (a region's strength the whole one's) starts at its value
function slider(option, id, options) {
  const start = option.default ?? options[option.page.follows].default;
  return Object.assign(document.createElement("input"), {
    type: "range", id, name: option.key, className: "strength", min: option.minimum, max: option.maximum, step: option.page.step, value: start,
  });
}

// one option's control in `box`, as its kind asks: a menu, a checkbox or a slider (with its value shown beside it); with
// `explained`, the menu or checkbox in a paragraph of its own with the option's plain sentence under it
function drawControl(box, option, prefix, options, explained) {
  const id = controlId(prefix, option);
  const place = explained ? Object.assign(document.createElement("p"), { className: "option" }) : box;
  let control = null;
  if (option.page.choices.length) {
    control = menu(option, id);
    const wrap = label(option, id);
    wrap.append(" ", control);
    place.append(wrap);
  } else if (option.kind === "boolean") {
    control = checkbox(option, id);
    const wrap = label(option, id);
    wrap.prepend(control, " ");
    place.append(wrap);
  } else if (option.minimum !== null && option.maximum !== null) {
    control = slider(option, id, options);
    box.append(label(option, id), control, Object.assign(document.createElement("output"), { htmlFor: id, textContent: control.value }));
    return control;
  }
  if (control && explained) {
    place.append(Object.assign(document.createElement("small"), { textContent: option.page.sentence }));
    box.append(place);
  }
  return control; // (null for a text option with no values to offer: the page draws nothing for it)
}

// Every element [data-sections] of the page gets a control for each option offered on `surface` ("form" or "json")
// whose page section is one of its sections, section by section in the order it lists them (its data-prefix starts
// their ids; with the class "explained", each with its plain sentence). Resolves to the controls drawn, each knowing its
// option (control.option).
async function drawOptions(surface) {
  const options = await describedOptions;
  const drawn = [];
  for (const box of document.querySelectorAll("[data-sections]")) {
    const end = box.querySelector(":scope > [data-options-end]"); // what the page keeps after the controls
    const place = document.createDocumentFragment();
    for (const section of box.dataset.sections.split(" ")) {
      for (const option of Object.values(options)) {
        if (!option.page || !option.surfaces.includes(surface) || option.page.section !== section) continue;
        const control = drawControl(place, option, box.dataset.prefix || "", options, box.classList.contains("explained"));
        if (control) drawn.push(Object.assign(control, { option }));
      }
    }
    box.insertBefore(place, end);
  }
  followSliders(drawn);
  return drawn;
}

function showValue(control) {
  const shown = document.querySelector(`output[for="${control.id}"]`);
  if (shown) shown.textContent = control.value;
}

// a slider that follows another takes its value as it moves, until moved itself
function followSliders(drawn) {
  for (const control of drawn.filter((c) => c.type === "range")) {
    control.addEventListener("input", () => {
      if (control.option.page.follows) control.dataset.moved = "true";
      for (const other of drawn) {
        if (other.option.page.follows === control.option.key && !other.dataset.moved) { other.value = control.value; showValue(other); }
      }
      showValue(control);
    });
  }
}

// the sliders back at their start (a follower at its leader's), none moved
function resetSliders(drawn) {
  const sliders = drawn.filter((c) => c.type === "range");
  for (const control of sliders) {
    delete control.dataset.moved;
    const leader = sliders.find((other) => other.option.key === control.option.page.follows);
    control.value = control.option.default ?? leader.option.default;
    showValue(control);
  }
}

// The controls' values as {key: value}, typed for `json` (a live message) or as a form's texts; left out: a menu's entry
// that sends nothing, and from a form a follower not moved (the server's default follows the same way; a live message
// says it, since a message changes only what it says).
function optionValues(controls, json = false) {
  const values = {};
  for (const control of controls) {
    const option = control.option;
    if ((control.tagName === "SELECT" && control.value === "") || (!json && option.page.follows && !control.dataset.moved)) continue;
    if (control.type === "checkbox") values[option.key] = json ? control.checked : String(control.checked);
    else if (json && (option.kind === "integer" || option.kind === "number")) values[option.key] = Number(control.value);
    else values[option.key] = control.value;
  }
  return values;
}

// How a record's options differ from the defaults, in words: "<option> <value>", "no <switch>", "<region> <strength>" (a region whose
// strength is not the whole one's), the landmarker when not the default's.
function optionsSaid(record, options) {
  const said = [];
  const words = (key) => key.replace(/_/g, " ");
  for (const [key, value] of Object.entries(record.options)) {
    if (key === "region_strengths") {
      said.push(...Object.entries(value).filter(([, s]) => s !== record.options.strength).map(([region, s]) => `${region} ${s}`));
    } else if (options[key] && value !== options[key].default) {
      said.push(typeof value === "boolean" ? `${value ? "" : "no "}${words(key)}` : `${words(key)} ${[].concat(value).join(",")}`);
    }
  }
  if (record.landmarker && options.landmarker && record.landmarker !== options.landmarker.default) said.push(`${record.landmarker} landmarks`);
  return said;
}
