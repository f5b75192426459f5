// The strength sliders of exprclone's pages (the clone page and live): the whole expression's, each region's (following
// the whole one's until moved) and the shading's, made inside the page's fieldset#strengths. No build step: a classic
// script, loaded before the page's own.
"use strict";

// [form field (exprclone.options.Options), label]
const STRENGTHS = [
  ["strength", "Whole expression"],
  ["strength_mouth", "Mouth"],
  ["strength_eyes", "Eyes"],
  ["strength_brows", "Brows"],
  ["strength_shading", "Shading (folds and shadows)"],
];
const REGION_STRENGTHS = ["strength_mouth", "strength_eyes", "strength_brows"];

const strengthSliders = () => [...document.querySelectorAll("input.strength")];

function showStrength(slider) {
  document.querySelector(`output[for="${slider.id}"]`).textContent = slider.value;
}

// the sliders made, and onInput (as one moves) and onChange (when one is let go, or reset) called
function makeStrengths(onInput, onChange) {
  const box = document.querySelector("#strengths");
  for (const [option, label] of STRENGTHS) {
    const id = option.replace("_", "-");
    box.insertAdjacentHTML("beforeend", `<label for="${id}">${label}</label>
      <input type="range" id="${id}" class="strength" data-option="${option}" min="0" max="2" step="0.1" value="1">
      <output for="${id}">1</output>`);
    const slider = document.getElementById(id);
    slider.addEventListener("input", () => {
      if (REGION_STRENGTHS.includes(option)) slider.dataset.moved = "true";
      if (option === "strength") {
        for (const region of strengthSliders()) {
          if (REGION_STRENGTHS.includes(region.dataset.option) && !region.dataset.moved) { region.value = slider.value; showStrength(region); }
        }
      }
      showStrength(slider);
      onInput();
    });
    slider.addEventListener("change", onChange);
  }
  box.insertAdjacentHTML("beforeend", '<button type="button" id="strengths-reset">Reset</button>');
  document.querySelector("#strengths-reset").addEventListener("click", () => {
    for (const slider of strengthSliders()) { slider.value = 1; delete slider.dataset.moved; showStrength(slider); }
    onChange();
  });
}

// the strengths as {form field: text}: the whole one always, a region's once moved, the shading's unless 1
function strengthsAsked() {
  const asked = {};
  for (const slider of strengthSliders()) {
    const option = slider.dataset.option;
    if (REGION_STRENGTHS.includes(option) ? slider.dataset.moved : option === "strength" || slider.value !== "1") asked[option] = slider.value;
  }
  return asked;
}
