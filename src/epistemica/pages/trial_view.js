// epistemica trial replay: the map, each robot's belief, configuration-set sizes (own and
// nested) and the events observed, for one trace (format epistemica-trace, version 1 or 2).
// The page state is exposed as window.epistemicaView for scripts and tests.
"use strict";
(function () {
  const page = JSON.parse(document.getElementById("data").textContent);
  const t = page.trace, colours = page.colours, focus = page.focus;
  const n = t.robots.length, m = t.goals.length, last = t.steps;
  const SVG = "http://www.w3.org/2000/svg";
  const colour = (i) => colours[i % colours.length];

  function el(tag, attrs, parent, text) {
    const node = tag.startsWith("svg:")
      ? document.createElementNS(SVG, tag.slice(4)) : document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
    if (text !== undefined) node.textContent = text;
    if (parent) parent.appendChild(node);
    return node;
  }

  // Layout: controls, then the map beside the panels.
  const app = document.getElementById("app");
  const controls = el("div", { class: "controls" }, app);
  const play = el("button", { id: "play", type: "button" }, controls, "Play");
  const slider = el("input", { id: "step", type: "range", min: 0, max: last, value: 0 }, controls);
  const label = el("span", { id: "step-label" }, controls);
  const row = el("div", { class: "row" }, app);
  const left = el("div", { class: "panel" }, row);
  const right = el("div", { class: "panel" }, row);

  // The map: world coordinates in metres, y up.
  const pts = [];
  t.poses.forEach((s) => s.forEach((p) => pts.push(p)));
  t.goal_positions.forEach((g) => pts.push(g));
  const xs = pts.map((p) => p[0]).filter(Number.isFinite);
  const ys = pts.map((p) => p[1]).filter(Number.isFinite);
  const lo = [Math.min(0, ...xs) - 1, Math.min(0, ...ys) - 1];
  const hi = [Math.max(t.workspace, ...xs) + 1, Math.max(t.workspace, ...ys) + 1];
  const size = 520, scale = size / Math.max(hi[0] - lo[0], hi[1] - lo[1]);
  const X = (x) => (x - lo[0]) * scale, Y = (y) => size - (y - lo[1]) * scale;
  const map = el("svg:svg", { id: "map", width: size, height: size,
    viewBox: `0 0 ${size} ${size}` }, left);
  t.goal_positions.forEach((g, k) => {
    el("svg:circle", { cx: X(g[0]), cy: Y(g[1]), r: t.success_radius * scale,
      fill: "#ccc", "fill-opacity": 0.5, class: "goal-area" }, map);
    const star = [];
    for (let p = 0; p < 10; p++) {
      const a = Math.PI / 2 + (p * Math.PI) / 5, r = p % 2 ? 4 : 10;
      star.push(`${X(g[0]) + r * Math.cos(a)},${Y(g[1]) - r * Math.sin(a)}`);
    }
    el("svg:polygon", { points: star.join(" "), fill: "#000", stroke: "#fff",
      class: "goal", "data-name": t.goals[k] }, map);
    el("svg:text", { x: X(g[0]) + 9, y: Y(g[1]) - 7, "font-size": 13, "font-weight": 700 },
      map, t.goals[k]);
  });
  const layer = el("svg:g", { id: "moving" }, map);
  const legend = el("div", { class: "legend" }, left);
  t.robots.forEach((r, i) => {
    const s = el("span", {}, legend);
    el("span", { class: "swatch", style: `background:${colour(i)}` }, s);
    s.appendChild(document.createTextNode(`${r} (${t.sensors[i]}, ${t.policies[i]})`));
  });
  el("div", { class: "note" }, left, "★ goal (grey disc: success radius); dashed circle: "
    + "sensing radius; × in a robot's colour: where it places a teammate; ring: observed an "
    + "event at this step");

  // Belief table: rows robots, columns goals, grey level = probability.
  el("h2", {}, right, "Each robot's belief that a goal is its own");
  const table = el("table", { id: "belief" }, right);
  const head = el("tr", {}, table);
  el("th", {}, head, "");
  t.goals.forEach((g) => el("th", {}, head, g));
  const cells = t.robots.map((r, i) => {
    const tr = el("tr", {}, table);
    el("th", { style: `color:${colour(i)}` }, tr, r);
    return t.goals.map(() => el("td", {}, tr, ""));
  });

  // Configuration-set sizes: own (solid) and the focus robot's model of each teammate's.
  el("h2", {}, right, `Configuration sets: own (solid), ${t.robots[focus]}'s model of each `
    + "teammate's (dashed)");
  const W = 460, H = 190, pad = 38;
  const chart = el("svg:svg", { id: "sets", width: W, height: H }, right);
  const own = t.considered, nested = t.modelled;
  const values = [];
  own.forEach((s) => s.forEach((v) => values.push(v)));
  nested.forEach((s) => s[focus].forEach((v) => values.push(v)));
  const top = Math.max(1, ...values), logScale = top > 20;
  const cx = (s) => pad + (s / Math.max(1, own.length - 1)) * (W - pad - 8);
  const cy = (v) => {
    const f = logScale ? Math.log(Math.max(v, 1)) / Math.log(top) : v / top;
    return H - 24 - f * (H - 34);
  };
  el("svg:line", { x1: pad, y1: H - 24, x2: W - 8, y2: H - 24, stroke: "#888" }, chart);
  el("svg:line", { x1: pad, y1: 10, x2: pad, y2: H - 24, stroke: "#888" }, chart);
  el("svg:text", { x: 2, y: 16, "font-size": 11 }, chart, String(top));
  el("svg:text", { x: 2, y: H - 24, "font-size": 11 }, chart, logScale ? "1" : "0");
  el("svg:text", { x: W - 60, y: H - 6, "font-size": 11 }, chart, "step →");
  const line = (series, i, dashed) => el("svg:polyline", {
    points: series.map((v, s) => `${cx(s)},${cy(v)}`).join(" "), fill: "none",
    stroke: colour(i), "stroke-width": dashed ? 1.5 : 2, "stroke-dasharray": dashed ? "5 4" : "",
    class: dashed ? "nested" : "own" }, chart);
  t.robots.forEach((r, i) => line(own.map((s) => s[i]), i, false));
  t.robots.forEach((r, j) => { if (j !== focus) line(nested.map((s) => s[focus][j]), j, true); });
  const cursor = el("svg:line", { y1: 10, y2: H - 24, stroke: "#555" }, chart);
  const key = el("div", { class: "legend", id: "sets-legend" }, right);
  t.robots.forEach((r, j) => {
    el("span", { style: `color:${colour(j)}` }, key,
      j === focus ? `━ ${r}` : `━ ${r}  ╌ ${t.robots[focus]}'s model of ${r}'s`);
  });

  // What one robot reads of its teammates' behaviour (teammate models), where kept.
  const types = t.teammate_types || null;
  const kept = types ? t.robots.map((r, i) => i)
    .filter((i) => types.some((s) => s[i].some((row) => row.every((v) => v !== null)))) : [];
  const reader = kept.includes(focus) ? focus : kept[0];
  let reading = null;
  if (kept.length) {
    el("h2", {}, right, `What ${t.robots[reader]} reads of its teammates' behaviour`);
    reading = el("div", { class: "events", id: "reading" }, right);
  }

  el("h2", {}, right, "Events observed (and by whom)");
  const events = el("div", { class: "events", id: "events" }, right);

  function eventText(e) {
    const seen = e[3].map((o) => t.robots[o]).join(", ") || "nobody";
    // Version 2 names the event's arguments; version 1 gave bare indices (not shown).
    const named = e[2].filter((a) => typeof a === "string" && a);
    const about = named.length ? `(${named.join(", ")})` : "";
    return `step ${e[0]}: ${e[1]}${about}, seen by ${seen}`;
  }

  function drawMap(step) {
    layer.replaceChildren();
    const pose = t.poses[step], decided = Math.min(step, last - 1);
    for (let i = 0; i < n; i++) {
      const trail = t.poses.slice(0, step + 1).map((p) => `${X(p[i][0])},${Y(p[i][1])}`);
      el("svg:polyline", { points: trail.join(" "), fill: "none", stroke: colour(i),
        "stroke-width": 1.5, "stroke-opacity": 0.7 }, layer);
      if (t.sensing_range !== null) {
        el("svg:circle", { cx: X(pose[i][0]), cy: Y(pose[i][1]), r: t.sensing_range * scale,
          fill: "none", stroke: colour(i), "stroke-dasharray": "6 4", class: "sensing",
          "data-robot": t.robots[i] }, layer);
      }
    }
    if (decided >= 0) {
      for (let i = 0; i < n; i++) {
        for (let j = 0; j < n; j++) {
          const e = t.estimates[decided][i][j];
          if (i === j || e[0] === null || e[1] === null) continue;
          el("svg:line", { x1: X(e[0]), y1: Y(e[1]), x2: X(pose[j][0]), y2: Y(pose[j][1]),
            stroke: colour(i), "stroke-opacity": 0.5 }, layer);
          el("svg:text", { x: X(e[0]), y: Y(e[1]) + 5, "text-anchor": "middle",
            "font-size": 15, fill: colour(i), class: "estimate" }, layer, "×");
        }
      }
    }
    for (const e of t.events) {
      if (e[0] !== step) continue;
      for (const o of e[3]) {
        el("svg:circle", { cx: X(pose[o][0]), cy: Y(pose[o][1]), r: 14, fill: "none",
          stroke: colour(o), "stroke-width": 3, class: "event-ring" }, layer);
      }
    }
    for (let i = 0; i < n; i++) {
      const [x, y, h] = pose[i];
      el("svg:line", { x1: X(x), y1: Y(y), x2: X(x + 1.4 * Math.cos(h)),
        y2: Y(y + 1.4 * Math.sin(h)), stroke: colour(i), "stroke-width": 3 }, layer);
      el("svg:circle", { cx: X(x), cy: Y(y), r: 7, fill: colour(i), stroke: "#000",
        class: "robot", "data-robot": t.robots[i] }, layer);
    }
  }

  function drawPanels(step) {
    const decided = Math.min(step, last - 1);
    cells.forEach((row, i) => row.forEach((cell, g) => {
      const v = decided >= 0 ? t.goal_belief[decided][i][g] : null;
      const grey = v === null ? 255 : Math.round(255 * (1 - v));
      cell.textContent = v === null ? "–" : v.toFixed(2);
      cell.style.background = `rgb(${grey},${grey},${grey})`;
      cell.style.color = v !== null && v > 0.55 ? "#fff" : "#000";
    }));
    cursor.setAttribute("x1", cx(Math.max(decided, 0)));
    cursor.setAttribute("x2", cx(Math.max(decided, 0)));
    if (reading) {
      reading.replaceChildren();
      types[Math.max(decided, 0)][reader].forEach((row, j) => {
        if (j === reader || row.some((v) => v === null)) return;
        const k = row.indexOf(Math.max(...row));
        el("div", {}, reading, `${t.robots[j]}: ${t.types[k]} ${row[k].toFixed(2)}`);
      });
    }
    events.replaceChildren();
    const seen = t.events.filter((e) => e[0] <= step);
    if (!seen.length) el("div", {}, events, "(none yet)");
    seen.forEach((e) => el("div", { class: e[0] === step ? "now" : "" }, events, eventText(e)));
  }

  const state = {
    step: 0, playing: false, timer: null, last: last,
    setStep(step) {
      state.step = Math.max(0, Math.min(last, Math.round(step)));
      slider.value = state.step;
      const outcome = t.success ? `success at step ${last}` : `failed (${last} steps)`;
      label.textContent = `step ${state.step} of ${last} (${outcome})`;
      drawMap(state.step);
      drawPanels(state.step);
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
