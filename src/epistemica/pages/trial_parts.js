// epistemica trial replay, the parts every column shares whatever the mission's kind: DOM and
// SVG helpers, a table of robots by goals or tasks, a chosen robot's table of its teammates,
// the map (axes in metres,
// scale bar, obstacles, goals or tasks, trails, sensing circles, event rings, robots) and the
// estimates overlay of goal traces. The page's one script is trial_parts.js, trial_panels.js
// (the panels, by name) and trial_view.js (the columns, the slider), in that order.

// The parts, drawing robot i in colours[i % colours.length].
function epistemicaParts(colours) {
  "use strict";
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

  // A round step for axis ticks: 1, 2 or 5 times a power of ten, about `count` ticks.
  function tickStep(span, count) {
    const raw = span / Math.max(count, 1), p = Math.pow(10, Math.floor(Math.log10(raw)));
    return [1, 2, 5, 10].map((f) => f * p).find((s) => s >= raw);
  }

  // A table of robots (rows, in their colours) by goals or tasks (columns), then the
  // columns `extra` names ([class, heading] each); its goal headings and cells.
  function robotTable(parent, attrs, t, rows, extra) {
    const table = el("table", attrs, parent);
    const head = el("tr", {}, table);
    el("th", {}, head, "");
    const heads = t.goals.map((g) => el("th", {}, head, g));
    (extra || []).forEach(([, heading]) => el("th", {}, head, heading));
    const cells = rows.map((i) => {
      const tr = el("tr", { "data-robot": t.robots[i] }, table);
      el("th", { style: `color:${colour(i)}` }, tr, t.robots[i]);
      return { goals: t.goals.map(() => el("td", { class: "goal-cell" }, tr, "")),
        extra: (extra || []).map(([name]) => el("td", { class: name }, tr, "")) };
    });
    return { heads, cells };
  }

  // A chosen robot's table of its teammates (rows) by goals or tasks, then the `extra`
  // columns: a select of the robot in a heading (`text` after it; first the focus robot),
  // the table rebuilt when another is chosen and redrawn by `redraw(step)`. The robot and
  // the table now: view.who, view.table (robotTable's).
  function teammateTable(ctx, attrs, extra, text, redraw) {
    const t = ctx.t, view = { who: ctx.focus, table: null };
    const title = el("h3", {}, ctx.col, "");
    const chooser = el("select", { class: "model-robot", id: `model-robot-${ctx.k}` }, title);
    t.robots.forEach((r, i) => {
      const option = el("option", { value: i }, chooser, r);
      if (i === ctx.focus) option.selected = true;
    });
    title.append(text);
    const holder = el("div", {}, ctx.col);
    const build = (who) => {
      view.who = who;
      holder.replaceChildren();
      view.table = robotTable(holder, attrs, t, t.robots.map((r, j) => j).filter((j) => j !== who),
        extra);
    };
    chooser.addEventListener("change", () => {
      build(Number(chooser.value));
      redraw(Math.min(window.epistemicaView.step, t.steps));
    });
    build(ctx.focus);
    return view;
  }

  // Closed goals per step, from the optional `closed` changes.
  function closedSteps(t) {
    const closedAt = [], closing = {};
    let shut = t.goals.map(() => false);
    (t.closed || []).forEach((c) => (closing[c[0]] = closing[c[0]] || []).push(c));
    for (let s = 0; s <= t.steps; s++) {
      if (closing[s]) {
        shut = shut.slice();
        for (const [, g, v] of closing[s]) shut[g] = !!v;
      }
      closedAt.push(shut);
    }
    return closedAt;
  }

  // The map's axes (ticks in metres from `lo`, over `span`) and scale bar (one tick long).
  function drawAxes(map, X, Y, lo, span, scale) {
    const size = +map.getAttribute("width"), margin = X(lo[0]);
    const tick = tickStep(span, 6), axes = el("svg:g", { class: "axes" }, map);
    el("svg:line", { x1: margin, y1: size - margin, x2: size - 4, y2: size - margin,
      stroke: "#888" }, axes);
    el("svg:line", { x1: margin, y1: 4, x2: margin, y2: size - margin, stroke: "#888" }, axes);
    for (let v = Math.ceil(lo[0] / tick) * tick; v <= lo[0] + span; v += tick) {
      el("svg:line", { x1: X(v), x2: X(v), y1: size - margin, y2: size - margin + 4,
        stroke: "#888" }, axes);
      el("svg:text", { x: X(v), y: size - margin + 15, "text-anchor": "middle",
        "font-size": 10, class: "tick x" }, axes, String(+v.toFixed(6)));
    }
    for (let v = Math.ceil(lo[1] / tick) * tick; v <= lo[1] + span; v += tick) {
      el("svg:line", { x1: margin - 4, x2: margin, y1: Y(v), y2: Y(v), stroke: "#888" }, axes);
      el("svg:text", { x: margin - 6, y: Y(v) + 3, "text-anchor": "end", "font-size": 10,
        class: "tick y" }, axes, String(+v.toFixed(6)));
    }
    el("svg:text", { x: size - 6, y: size - 3, "text-anchor": "end", "font-size": 10 }, axes,
      "x (m)");
    el("svg:text", { x: 3, y: 12, "font-size": 10 }, axes, "y (m)");
    const bar = el("svg:g", { class: "scale-bar" }, map);
    el("svg:line", { x1: size - 14 - tick * scale, x2: size - 14, y1: size - margin - 10,
      y2: size - margin - 10, stroke: "#000", "stroke-width": 3 }, bar);
    el("svg:text", { x: size - 14 - (tick * scale) / 2, y: size - margin - 15,
      "text-anchor": "middle", "font-size": 11 }, bar, `${tick} m`);
  }

  // Goals (tasks) as stars on discs of their success radius, named; [star, name] each.
  function drawGoals(map, t, X, Y, scale) {
    const size = +map.getAttribute("width");
    return t.goal_positions.map((g, j) => {
      el("svg:circle", { cx: X(g[0]), cy: Y(g[1]), r: t.success_radius * scale,
        fill: "#ccc", "fill-opacity": 0.5, class: "goal-area" }, map);
      const star = [];
      for (let q = 0; q < 10; q++) {
        const a = Math.PI / 2 + (q * Math.PI) / 5, r = q % 2 ? 4 : 10;
        star.push(`${X(g[0]) + r * Math.cos(a)},${Y(g[1]) - r * Math.sin(a)}`);
      }
      const mark = el("svg:polygon", { points: star.join(" "), class: "goal",
        "data-name": t.goals[j] }, map);
      const right = X(g[0]) > 0.65 * size;  // named on its left near the right edge
      const name = el("svg:text", { x: X(g[0]) + (right ? -9 : 9), y: Y(g[1]) - 7,
        "text-anchor": right ? "end" : "start", "font-size": 13, "font-weight": 700,
        class: "goal-name" }, map, t.goals[j]);
      return [mark, name];
    });
  }

  // The map: world coordinates in metres, y up, with axes and a scale bar; goals (tasks),
  // obstacles; each step the trails, sensing circles, event rings and robots, and what the
  // panels add (ctx.overlays).
  function buildMap(ctx) {
    const t = ctx.t, k = ctx.k, n = ctx.n;
    const pts = [];
    t.poses.forEach((s) => s.forEach((q) => pts.push(q)));
    t.goal_positions.forEach((g) => pts.push(g));
    (t.obstacles || []).forEach((poly) => poly.forEach((q) => pts.push(q)));
    const xs = pts.map((q) => q[0]).filter(Number.isFinite);
    const ys = pts.map((q) => q[1]).filter(Number.isFinite);
    const lo = [Math.min(0, ...xs) - 1, Math.min(0, ...ys) - 1];
    const hi = [Math.max(t.workspace, ...xs) + 1, Math.max(t.workspace, ...ys) + 1];
    const size = 430, margin = 30, span = Math.max(hi[0] - lo[0], hi[1] - lo[1]);
    const scale = (size - margin - 6) / span;
    const X = (x) => margin + (x - lo[0]) * scale, Y = (y) => size - margin - (y - lo[1]) * scale;
    Object.assign(ctx, { X, Y, scale });
    const map = el("svg:svg", { class: "map", id: `map-${k}`, width: size, height: size,
      viewBox: `0 0 ${size} ${size}` }, ctx.col);
    drawAxes(map, X, Y, lo, span, scale);
    (t.obstacles || []).forEach((poly) => el("svg:polygon", {
      points: poly.map((q) => `${X(q[0])},${Y(q[1])}`).join(" "), fill: "#777",
      "fill-opacity": 0.55, stroke: "#333", class: "obstacle" }, map));
    ctx.goalMarks = drawGoals(map, t, X, Y, scale);
    const layer = el("svg:g", { class: "moving" }, map);
    ctx.layer = layer;
    ctx.closedAt = closedSteps(t);
    // A goal drawn open (filled) or closed (hollow), named as `text` says.
    ctx.markGoal = (j, closed, text) => {
      const [mark, name] = ctx.goalMarks[j];
      mark.setAttribute("fill", closed ? "#fff" : "#000");
      mark.setAttribute("stroke", closed ? "#000" : "#fff");
      mark.setAttribute("stroke-width", closed ? 1.5 : 1);
      mark.classList.toggle("closed", closed);
      name.textContent = text;
    };

    ctx.drawMap = (step) => {
      layer.replaceChildren();
      const pose = t.poses[step];
      ctx.closedAt[step].forEach((c, j) => ctx.markGoal(j, c,
        c ? `${t.goals[j]} (closed)` : t.goals[j]));
      for (let i = 0; i < n; i++) {
        const trail = t.poses.slice(0, step + 1).map((q) => `${X(q[i][0])},${Y(q[i][1])}`);
        el("svg:polyline", { points: trail.join(" "), fill: "none", stroke: colour(i),
          "stroke-width": 1.5, "stroke-opacity": 0.7 }, layer);
        if (t.sensing_range !== null) {
          el("svg:circle", { cx: X(pose[i][0]), cy: Y(pose[i][1]), r: t.sensing_range * scale,
            fill: "none", stroke: colour(i), "stroke-dasharray": "6 4", class: "sensing",
            "data-robot": t.robots[i] }, layer);
        }
      }
      ctx.overlays.forEach((draw) => draw(step, pose));
      for (const e of t.events) {
        if (e[0] !== step) continue;
        for (const o of e[3]) {
          el("svg:circle", { cx: X(pose[o][0]), cy: Y(pose[o][1]), r: 16, fill: "none",
            stroke: colour(o), "stroke-width": 3, class: "event-ring" }, layer);
        }
      }
      // Robots: one drawn where an earlier one already is (within a marker) gets a wider
      // ring, so that a robot under another stays visible.
      const placed = [];
      for (let i = 0; i < n; i++) {
        const [x, y, h] = pose[i];
        const under = placed.filter((q) => Math.hypot(X(x) - q[0], Y(y) - q[1]) < 12).length;
        placed.push([X(x), Y(y)]);
        el("svg:line", { x1: X(x), y1: Y(y), x2: X(x + 1.4 * Math.cos(h)),
          y2: Y(y + 1.4 * Math.sin(h)), stroke: colour(i), "stroke-width": 3 }, layer);
        const r = 6 + 4 * under;
        el("svg:circle", under ? { cx: X(x), cy: Y(y), r: r, fill: "none", stroke: colour(i),
          "stroke-width": 3, class: "robot stacked", "data-robot": t.robots[i] }
          : { cx: X(x), cy: Y(y), r: r, fill: colour(i), stroke: "#000", class: "robot",
            "data-robot": t.robots[i] }, layer);
      }
    };
  }

  // Where each robot placed each teammate when it decided (goal traces: `estimates`).
  function estimatesOverlay(ctx) {
    const t = ctx.t, X = ctx.X, Y = ctx.Y;
    return (step, pose) => {
      const decided = Math.min(step, t.steps - 1);
      if (decided < 0) return;
      for (let i = 0; i < ctx.n; i++) {
        for (let j = 0; j < ctx.n; j++) {
          const e = t.estimates[decided][i][j];
          if (i === j || e[0] === null || e[1] === null) continue;
          el("svg:line", { x1: X(e[0]), y1: Y(e[1]), x2: X(pose[j][0]), y2: Y(pose[j][1]),
            stroke: colour(i), "stroke-opacity": 0.5 }, ctx.layer);
          el("svg:text", { x: X(e[0]), y: Y(e[1]) + 5, "text-anchor": "middle",
            "font-size": 15, fill: colour(i), class: "estimate" }, ctx.layer, "×");
        }
      }
    };
  }

  return { colour, el, tickStep, robotTable, teammateTable, buildMap, estimatesOverlay };
}
