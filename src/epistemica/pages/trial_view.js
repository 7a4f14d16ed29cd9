// epistemica trial replay: one column per trial (two levels of the same seed side by side),
// one shared slider. Each column: the map (obstacles, goals or tasks, axes in metres, sensing
// radii, events), then the panels its mission kind names (page.trials[k].panels, the kind's
// `panels`), each drawn by its builder in PANELS:
//   goal missions   knowledge (the goals each robot knows of and how, the configuration it
//                   acts on and its set; a chosen robot's model of each teammate's
//                   knowledge), belief, sets (configuration-set sizes, teammate reading),
//                   events; on the map, where each robot places each teammate;
//   joint missions  targets (what each robot steers to, on the map and in a table; tasks
//                   with the robots they need and when they were done), tasks_known (the
//                   tasks each robot knows of, since when and how), teammates_known (what a
//                   chosen robot knows each teammate knows of), events.
// Traces: format epistemica-trace, version 1 to 3; the knowledge fields are optional.
// The page state is exposed as window.epistemicaView for scripts and tests.
"use strict";
(function () {
  const page = JSON.parse(document.getElementById("data").textContent);
  const colours = page.colours;
  const SVG = "http://www.w3.org/2000/svg";
  const colour = (i) => colours[i % colours.length];
  const last = Math.max(...page.trials.map((p) => p.trace.steps));

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

  // A select of the robot whose model of its teammates a panel shows, in a heading.
  function robotChooser(ctx, id, text, onChange) {
    const title = el("h3", {}, ctx.col, "");
    const chooser = el("select", { class: "model-robot", id: id }, title);
    ctx.t.robots.forEach((r, i) => {
      const option = el("option", { value: i }, chooser, r);
      if (i === ctx.focus) option.selected = true;
    });
    title.append(text);
    chooser.addEventListener("change", () => onChange(Number(chooser.value)));
    return chooser;
  }

  const outcome = (t) => (t.success ? `succeeded at step ${t.steps}`
    : `failed: not done within ${t.steps} steps`);

  // Layout: shared controls, then one column per trial.
  const app = document.getElementById("app");
  const controls = el("div", { class: "controls" }, app);
  const play = el("button", { id: "play", type: "button" }, controls, "Play");
  const slider = el("input", { id: "step", type: "range", min: 0, max: last, value: 0 }, controls);
  const label = el("span", { id: "step-label" }, controls);
  const columns = el("div", { class: "row" }, app);

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
    (t.obstacles || []).forEach((poly) => el("svg:polygon", {
      points: poly.map((q) => `${X(q[0])},${Y(q[1])}`).join(" "), fill: "#777",
      "fill-opacity": 0.55, stroke: "#333", class: "obstacle" }, map));
    ctx.goalMarks = t.goal_positions.map((g, j) => {
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

  // ---- The panels of goal missions -------------------------------------------------------

  // What each robot knows: the goals it knows of (and how, from which step), the
  // configuration it acts on and the size of its configuration set; a chosen robot's model
  // of each teammate's knowledge.
  function knowledgePanel(ctx) {
    const t = ctx.t, n = ctx.n, k = ctx.k;
    // Knowledge per step, from the optional `knows` changes (absent: all common knowledge).
    const known = [], how = [];  // known[step][i][j][g]; how[i][j][g] = [step, how]
    const blank = () => t.robots.map(() => t.robots.map(() => t.goals.map(() => false)));
    let now = t.knows ? blank() : t.robots.map(() => t.robots.map(() => t.goals.map(() => true)));
    for (let i = 0; i < n; i++) how.push(t.robots.map(() => t.goals.map(() => [0, "start"])));
    const byStep = {};
    (t.knows || []).forEach((c) => (byStep[c[0]] = byStep[c[0]] || []).push(c));
    for (let s = 0; s <= t.steps; s++) {
      if (byStep[s]) {
        now = now.map((a) => a.map((b) => b.slice()));
        for (const [step, i, j, g, v, h] of byStep[s]) {
          now[i][j][g] = !!v;
          if (v) how[i][j][g] = [step, h];
        }
      }
      known.push(now);
    }
    el("h3", {}, ctx.col, "What each robot knows (✓ knows of the goal: how, step; · does not; "
      + "red: expects a teammate at a goal it takes the teammate not to know of)");
    const own = robotTable(ctx.col, { class: "knowledge", id: `knowledge-${k}` }, t,
      t.robots.map((r, i) => i), [["acts", "acts on"], ["sets", "configurations"]]);
    let modeller = ctx.focus, model = null;
    const mt = el("div", {}, ctx.col);
    robotChooser(ctx, `model-robot-${k}`, "'s model of what each teammate knows (✓ it takes "
      + "the teammate to know of the goal; ✗ not; red: wrong)", (who) => {
      buildModel(who);
      draw(Math.min(window.epistemicaView.step, t.steps));
    });
    ctx.col.appendChild(mt);
    function buildModel(who) {
      modeller = who;
      mt.replaceChildren();
      model = robotTable(mt, { class: "model", id: `model-${k}` }, t,
        t.robots.map((r, j) => j).filter((j) => j !== who), [["sets", "set it models"]]);
    }
    buildModel(ctx.focus);

    function goalCell(cell, yes, h, closed, wrong) {
      cell.replaceChildren();
      cell.className = "goal-cell " + (yes ? "known" : "unknown") + (wrong ? " wrong" : "")
        + (closed ? " closed" : "");
      cell.appendChild(document.createTextNode(yes ? "✓" : "·"));
      if (yes && h) el("small", {}, cell, ` ${h[1]}${h[0] ? " " + h[0] : ""}`);
    }

    function draw(s) {
      const decided = Math.min(s, t.steps - 1);
      const K = known[s], shut = ctx.closedAt[s];
      own.heads.forEach((th, g) => (th.textContent = shut[g]
        ? `${t.goals[g]} (closed)` : t.goals[g]));
      own.cells.forEach((row, i) => {
        row.goals.forEach((cell, g) => {
          const h = K[i][i][g] && t.knows ? how[i][i][g] : null;
          goalCell(cell, K[i][i][g], h && h[0] <= s ? h : [0, "start"], shut[g], false);
        });
        const [acts, sets] = row.extra;
        const focal = decided >= 0 ? t.focal[decided][i] : null;
        if (!focal || focal[i] < 0) {
          acts.textContent = "not computed";
          acts.className = "acts not-computed";
        } else {
          // An expectation the robot's own knowledge contradicts (it takes the teammate
          // not to know of that goal) is marked: the reason a lower level fails.
          acts.replaceChildren(`heads for ${t.goals[focal[i]]}`);
          acts.className = "acts";
          focal.forEach((g, j) => {
            if (j === i || g < 0) return;
            acts.append(acts.childNodes.length > 1 ? ", " : "; expects ");
            el("span", K[i][j][g] ? { class: "expect" } : { class: "expect wrong",
              title: `${t.robots[i]} takes ${t.robots[j]} not to know of ${t.goals[g]}` },
            acts, `${t.robots[j]}→${t.goals[g]}`);
          });
        }
        const c = decided >= 0 ? t.considered[decided][i] : 0;
        const u = decided >= 0 && t.unpruned ? t.unpruned[decided][i] : c;
        sets.textContent = c > 0 ? (u > c ? `${c} (of ${u})` : String(c)) : "not computed";
        sets.className = c > 0 ? "sets" : "sets not-computed";
      });
      const others = t.robots.map((r, j) => j).filter((j) => j !== modeller);
      model.cells.forEach((row, r) => {
        const j = others[r];
        row.goals.forEach((cell, g) => {
          const yes = K[modeller][j][g], wrong = yes !== K[j][j][g];
          cell.replaceChildren();
          cell.className = "goal-cell " + (yes ? "known" : "unknown") + (wrong ? " wrong" : "");
          cell.textContent = yes ? "✓" : "✗";
        });
        const v = decided >= 0 ? t.modelled[decided][modeller][j] : 0;
        row.extra[0].textContent = v > 0 ? String(v) : "not computed";
        row.extra[0].className = v > 0 ? "sets" : "sets not-computed";
      });
    }
    return draw;
  }

  // Belief table: rows robots, columns goals, grey level = probability.
  function beliefPanel(ctx) {
    const t = ctx.t;
    el("h3", {}, ctx.col, "Each robot's belief that a goal is its own (n/c: not computed)");
    const table = el("table", { class: "belief", id: `belief-${ctx.k}` }, ctx.col);
    const head = el("tr", {}, table);
    el("th", {}, head, "");
    t.goals.forEach((g) => el("th", {}, head, g));
    const cells = t.robots.map((r, i) => {
      const tr = el("tr", {}, table);
      el("th", { style: `color:${colour(i)}` }, tr, r);
      return t.goals.map(() => el("td", {}, tr, ""));
    });
    return (step) => {
      const decided = Math.min(step, t.steps - 1);
      cells.forEach((row, i) => {
        const beliefs = decided >= 0 ? t.goal_belief[decided][i] : null;
        const computed = beliefs && beliefs.some((v) => v !== null && v > 0);
        row.forEach((cell, g) => {
          const v = computed ? beliefs[g] : null;
          const grey = v === null ? 255 : Math.round(255 * (1 - v));
          cell.textContent = v === null ? "n/c" : v.toFixed(2);
          cell.className = v === null ? "not-computed" : "";
          cell.style.background = v === null ? "" : `rgb(${grey},${grey},${grey})`;
          cell.style.color = v !== null && v > 0.55 ? "#fff" : "";
        });
      });
    };
  }

  // Configuration-set sizes: own (solid) and the focus robot's model of each teammate's;
  // what the focus robot (else the first that kept any) reads of its teammates' behaviour.
  function setsPanel(ctx) {
    const t = ctx.t, k = ctx.k, focus = ctx.focus, col = ctx.col;
    el("h3", {}, col, `Configuration sets: own (solid), ${t.robots[focus]}'s model of each `
      + "teammate's (dashed, wide)");
    const W = 430, H = 170, padL = 44, padB = 30;
    const chart = el("svg:svg", { class: "sets-chart", id: `sets-${k}`, width: W, height: H },
      col);
    const own = t.considered, nested = t.modelled;
    const values = [];
    own.forEach((s) => s.forEach((v) => values.push(v)));
    nested.forEach((s) => s[focus].forEach((v) => values.push(v)));
    const top = Math.max(1, ...values), logScale = top > 20;
    const cx = (s) => padL + (s / Math.max(1, t.steps)) * (W - padL - 10);
    const cy = (v) => {
      const f = logScale ? Math.log(Math.max(v, 1)) / Math.log(top) : v / top;
      return H - padB - f * (H - padB - 18);
    };
    el("svg:line", { x1: padL, y1: H - padB, x2: W - 8, y2: H - padB, stroke: "#888" }, chart);
    el("svg:line", { x1: padL, y1: 18, x2: padL, y2: H - padB, stroke: "#888" }, chart);
    const yt = logScale ? [1, 10, 100, 1000, 10000, 100000].filter((v) => v <= top)
      : [0, Math.round(top / 2), top].filter((v, i, a) => a.indexOf(v) === i);
    yt.forEach((v) => el("svg:text", { x: padL - 4, y: cy(v) + 4, "text-anchor": "end",
      "font-size": 10, class: "tick y" }, chart, String(v)));
    const xtick = tickStep(Math.max(t.steps, 1), 5);
    for (let s = 0; s <= t.steps; s += xtick) {
      el("svg:text", { x: cx(s), y: H - padB + 13, "text-anchor": "middle", "font-size": 10,
        class: "tick x" }, chart, String(s));
    }
    el("svg:text", { x: W - 10, y: H - 3, "text-anchor": "end", "font-size": 10 }, chart, "step");
    el("svg:text", { x: 2, y: 10, "font-size": 10 }, chart,
      logScale ? "configurations (log)" : "configurations");
    const line = (series, i, dashed) => el("svg:polyline", {
      points: series.map((v, s) => `${cx(s)},${cy(v)}`).join(" "), fill: "none",
      stroke: colour(i), "stroke-width": dashed ? 4 : 1.6, "stroke-opacity": dashed ? 0.45 : 1,
      "stroke-dasharray": dashed ? "6 4" : "", class: dashed ? "nested" : "own" }, chart);
    t.robots.forEach((r, j) => { if (j !== focus) line(nested.map((s) => s[focus][j]), j, true); });
    t.robots.forEach((r, i) => line(own.map((s) => s[i]), i, false));
    const cursor = el("svg:line", { y1: 18, y2: H - padB, stroke: "#555" }, chart);

    const types = t.teammate_types || null;
    const kept = types ? t.robots.map((r, i) => i)
      .filter((i) => types.some((s) => s[i].some((row) => row.every((v) => v !== null)))) : [];
    const reader = kept.includes(focus) ? focus : kept[0];
    let reading = null;
    if (kept.length) {
      el("h3", {}, col, `What ${t.robots[reader]} reads of its teammates' behaviour (the most `
        + "likely of the behaviour library, its posterior)");
      reading = el("div", { class: "events reading", id: `reading-${k}` }, col);
    }
    return (step) => {
      const decided = Math.min(step, t.steps - 1);
      cursor.setAttribute("x1", cx(Math.max(decided, 0)));
      cursor.setAttribute("x2", cx(Math.max(decided, 0)));
      if (reading) {
        reading.replaceChildren();
        types[Math.max(decided, 0)][reader].forEach((row, j) => {
          if (j === reader || row.some((v) => v === null)) return;
          const g = row.indexOf(Math.max(...row));
          el("div", {}, reading, `${t.robots[j]}: ${t.types[g]} ${row[g].toFixed(2)}`);
        });
      }
    };
  }

  // ---- The panels of joint (collaborative) missions ----------------------------------------

  const ACTIONS = { "-1": "explore", "-2": "fetch", "-3": "wait" };
  const target = (t, v) => ACTIONS[v] || `→${t.goals[v]}`;

  // What each robot steers to (beside it on the map, and in a table with the step it began);
  // each task named with the robots it needs and, once done, when.
  function targetsPanel(ctx) {
    const t = ctx.t, k = ctx.k;
    const name = (j, s) => `${t.goals[j]} ×${t.needs[j]}`
      + (t.tasks_done[j] >= 0 && t.tasks_done[j] <= s ? ` (done at ${t.tasks_done[j]})` : "");
    ctx.overlays.push((step, pose) => {
      const decided = Math.min(step, t.steps - 1);
      t.goals.forEach((g, j) => {
        const done = t.tasks_done[j] >= 0 && t.tasks_done[j] <= step;
        ctx.markGoal(j, done, name(j, step));
        ctx.goalMarks[j][0].classList.toggle("done", done);
      });
      if (decided < 0) return;
      t.robots.forEach((r, i) => el("svg:text", { x: ctx.X(pose[i][0]) + 9,
        y: ctx.Y(pose[i][1]) + 14, "font-size": 11, fill: colour(i), class: "target",
        "data-robot": r }, ctx.layer, target(t, t.steer_to[decided][i])));
    });
    el("h3", {}, ctx.col, "What each robot steers to (→ a task; explore; fetch: goes to tell "
      + "a teammate; wait: for helpers at a task), since which step");
    const table = el("table", { class: "targets", id: `targets-${k}` }, ctx.col);
    const rows = t.robots.map((r, i) => {
      const tr = el("tr", { "data-robot": r }, table);
      el("th", { style: `color:${colour(i)}` }, tr, r);
      return [el("td", { class: "target" }, tr, ""), el("td", { class: "since" }, tr, "")];
    });
    return (step) => {
      const decided = Math.min(step, t.steps - 1);
      rows.forEach(([what, since], i) => {
        if (decided < 0) {
          what.textContent = "not decided";
          since.textContent = "";
          return;
        }
        let first = decided;
        while (first > 0 && t.steer_to[first - 1][i] === t.steer_to[decided][i]) first--;
        what.textContent = target(t, t.steer_to[decided][i]);
        since.textContent = `since ${first}`;
      });
    };
  }

  // The tasks each robot knows of: since when (aware_since) and how (page: learned).
  function tasksKnownPanel(ctx) {
    const t = ctx.t, p = ctx.p;
    const how = t.robots.map(() => t.goals.map(() => null));
    (p.learned || []).forEach(([step, i, g, h]) => (how[i][g] = [step, h]));
    el("h3", {}, ctx.col, "The tasks each robot knows of (✓ how, since which step; · not yet; "
      + "×k: robots the task needs)");
    const tab = robotTable(ctx.col, { class: "knowledge tasks", id: `knowledge-${ctx.k}` }, t,
      t.robots.map((r, i) => i));
    return (step) => {
      const decided = Math.min(step, t.steps - 1);
      tab.heads.forEach((th, g) => {
        const done = t.tasks_done[g] >= 0 && t.tasks_done[g] <= step;
        th.textContent = `${t.goals[g]} ×${t.needs[g]}${done ? " (done)" : ""}`;
      });
      tab.cells.forEach((row, i) => row.goals.forEach((cell, g) => {
        const yes = decided >= 0 && !!t.tasks_known[decided][i][g];
        cell.replaceChildren(yes ? "✓" : "·");
        cell.className = "goal-cell " + (yes ? "known" : "unknown");
        const h = how[i][g];
        if (yes && h && h[0] <= step) el("small", {}, cell, ` ${h[1]} ${h[0]}`);
      }));
    };
  }

  // What a chosen robot knows each teammate knows of (aware_since[i][j][g] <= step).
  function teammatesKnownPanel(ctx) {
    const t = ctx.t, k = ctx.k;
    let who = ctx.focus, tab = null;
    const holder = el("div", {}, ctx.col);
    robotChooser(ctx, `model-robot-${k}`, " knows that each teammate knows of (✓ since which "
      + "step; · does not know it; amber: the teammate does know of it)", (chosen) => {
      build(chosen);
      draw(Math.min(window.epistemicaView.step, t.steps));
    });
    ctx.col.appendChild(holder);
    function build(chosen) {
      who = chosen;
      holder.replaceChildren();
      tab = robotTable(holder, { class: "model tasks", id: `model-${k}` }, t,
        t.robots.map((r, j) => j).filter((j) => j !== chosen));
    }
    build(ctx.focus);
    function draw(step) {
      const others = t.robots.map((r, j) => j).filter((j) => j !== who);
      tab.cells.forEach((row, r) => row.goals.forEach((cell, g) => {
        const j = others[r], since = t.aware_since[who][j][g];
        const yes = since >= 0 && since <= step;
        const theirs = t.aware_since[j][j][g] >= 0 && t.aware_since[j][j][g] <= step;
        cell.textContent = yes ? `✓ ${since}` : "·";
        cell.className = "goal-cell " + (yes ? "known" : "unknown")
          + (!yes && theirs ? " unaware" : "");
      }));
    }
    return draw;
  }

  // ---- Shared by every kind -------------------------------------------------------------

  function eventsPanel(ctx) {
    const t = ctx.t;
    el("h3", {}, ctx.col, "Events observed (and by whom)");
    const events = el("div", { class: "events", id: `events-${ctx.k}` }, ctx.col);
    function eventText(e) {
      const seen = e[3].map((o) => t.robots[o]).join(", ") || "nobody";
      const named = e[2].filter((a) => typeof a === "string" && a);
      const about = named.length ? `(${named.join(", ")})` : "";
      return `step ${e[0]}: ${e[1]}${about}, seen by ${seen}`;
    }
    return (step) => {
      events.replaceChildren();
      const seen = t.events.filter((e) => e[0] <= step);
      if (!seen.length) el("div", {}, events, "(none yet)");
      seen.forEach((e) => el("div", { class: e[0] === step ? "now" : "" }, events, eventText(e)));
    };
  }

  const PANELS = {
    knowledge: knowledgePanel, belief: beliefPanel, sets: setsPanel,
    targets: targetsPanel, tasks_known: tasksKnownPanel, teammates_known: teammatesKnownPanel,
    events: eventsPanel,
  };

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
