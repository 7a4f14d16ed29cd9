// epistemica trial replay: one column per trial (two levels of the same seed side by side),
// one shared slider. Each column: the map, then the panels its mission kind names
// (trial_panels.js), from the parts every kind shares (trial_parts.js).
// Traces: format epistemica-trace, version 1 to 3; the knowledge fields are optional.
// The page state is exposed as window.epistemicaView for scripts and tests.
(function () {
  "use strict";
  const page = JSON.parse(document.getElementById("data").textContent);
  const parts = epistemicaParts(page.colours);
  const PANELS = epistemicaPanels(parts);
  const { buildMap, colour, el, estimatesOverlay } = parts;
  const last = Math.max(...page.trials.map((p) => p.trace.steps));

  const outcome = (t) => (t.success ? `succeeded at step ${t.steps}`
    : `failed: not done within ${t.steps} steps`);

  // Layout: shared controls, then one column per trial.
  const app = document.getElementById("app");
  const controls = el("div", { class: "controls" }, app);
  const play = el("button", { id: "play", type: "button" }, controls, "Play");
  const slider = el("input", { id: "step", type: "range", min: 0, max: last, value: 0 }, controls);
  const label = el("span", { id: "step-label" }, controls);
  const columns = el("div", { class: "row" }, app);

  function column(p, k) {
    const t = p.trace;
    const col = el("div", { class: "column", id: `trial-${k}`, "data-level": p.level }, columns);
    el("h2", { class: "level" }, col, `${p.level}: ${outcome(t)}`);
    const ctx = { t, p, k, col, n: t.robots.length, focus: p.focus, overlays: [] };
    buildMap(ctx);
    if (t.estimates) ctx.overlays.push(estimatesOverlay(ctx));
    const legend = el("div", { class: "legend" }, col);
    t.robots.forEach((r, i) => {
      const s = el("span", {}, legend);
      el("span", { class: "swatch", style: `background:${colour(i)}` }, s);
      s.appendChild(document.createTextNode(`${r} (${t.sensors[i]}, ${t.policies[i]})`));
    });
    const joint = p.panels.includes("targets");
    el("div", { class: "note" }, col, (joint
      ? "★ task (×k: robots it needs at once; grey disc: completion radius; ☆ hollow: done); "
      : "★ goal (grey disc: success radius; ☆ hollow: closed); × in a robot's colour: where "
        + "it places a teammate; ")
      + "dark polygon: obstacle; dashed circle: sensing radius; ring: observed an event; a "
      + "robot under another is drawn as a wider ring around it");
    const draws = p.panels.filter((name) => PANELS[name]).map((name) => PANELS[name](ctx));
    return {
      draw(step) {
        const s = Math.min(step, t.steps);
        ctx.drawMap(s);
        draws.forEach((draw) => draw(s));
      },
    };
  }

  const views = page.trials.map((p, k) => column(p, k));

  const state = {
    step: 0, playing: false, timer: null, last: last,
    setStep(step) {
      state.step = Math.max(0, Math.min(last, Math.round(step)));
      slider.value = state.step;
      label.textContent = `step ${state.step} of ${last}`;
      views.forEach((v) => v.draw(state.step));
    },
    play() {
      if (state.playing) return;
      if (state.step >= last) state.setStep(0);
      state.playing = true;
      play.textContent = "Pause";
      state.timer = setInterval(() => {
        if (state.step >= last) { state.pause(); return; }
        state.setStep(state.step + 1);
      }, 1000 / page.fps);
    },
    pause() {
      state.playing = false;
      play.textContent = "Play";
      clearInterval(state.timer);
    },
  };
  play.addEventListener("click", () => (state.playing ? state.pause() : state.play()));
  slider.addEventListener("input", () => { state.pause(); state.setStep(Number(slider.value)); });
  window.epistemicaView = state;
  state.setStep(0);
})();
