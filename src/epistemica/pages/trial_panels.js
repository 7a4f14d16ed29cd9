// epistemica trial replay, the panels a column draws beside its map, by the names mission
// kinds give them (MissionKind.panels; page.trials[k].panels):
//   goal missions   knowledge (the goals each robot knows of and how, the configuration it
//                   acts on and its set; a chosen robot's model of each teammate's
//                   knowledge), belief, sets (configuration-set sizes, teammate reading),
//                   events;
//   joint missions  targets (what each robot steers to, on the map and in a table; tasks
//                   with the robots they need and when they were done), tasks_known (the
//                   tasks each robot knows of, since when and how), teammates_known (what a
//                   chosen robot knows each teammate knows of), events.
// Each builder takes the column's context (trace t, page data p, column index k, element col,
// the map's X, Y, layer, overlays, markGoal, closedAt) and returns its draw(step).

// The panel builders over `parts` (epistemicaParts), by name.
function epistemicaPanels(parts) {
  "use strict";
  const { colour, el, tickStep, robotTable, teammateTable } = parts;

  // ---- The panels of goal missions -------------------------------------------------------

  // Who takes whom to know of which goal at each step, from the optional `knows` changes
  // (absent: every goal common knowledge): [known[step][i][j][g], how[i][j][g] = [step, how]].
  function knownSteps(t) {
    const n = t.robots.length;
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
    return [known, how];
  }

  // What each robot knows: the goals it knows of (and how, from which step), the
  // configuration it acts on and the size of its configuration set; a chosen robot's model
  // of each teammate's knowledge.
  function knowledgePanel(ctx) {
    const t = ctx.t, k = ctx.k;
    const [known, how] = knownSteps(t);
    el("h3", {}, ctx.col, "What each robot knows (✓ knows of the goal: how, step; · does not; "
      + "red: expects a teammate at a goal it takes the teammate not to know of)");
    const own = robotTable(ctx.col, { class: "knowledge", id: `knowledge-${k}` }, t,
      t.robots.map((r, i) => i), [["acts", "acts on"], ["sets", "configurations"]]);
    const model = teammateTable(ctx, { class: "model", id: `model-${k}` },
      [["sets", "set it models"]], "'s model of what each teammate knows (✓ it takes the "
      + "teammate to know of the goal; ✗ not; red: wrong)", (step) => draw(step));
    if (ctx.p.focus_why) {  // the robot chosen first, and why (palette.focus_reason)
      el("div", { class: "note focus-why", id: `focus-why-${k}` }, ctx.col, ctx.p.focus_why);
    }

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
      const modeller = model.who, others = t.robots.map((r, j) => j).filter((j) => j !== modeller);
      model.table.cells.forEach((row, r) => {
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
    el("h3", {}, ctx.col, "Each robot's belief that a goal is its own, after the step's "
      + "observations (n/c: not computed)");
    el("div", { class: "note", id: `belief-why-${ctx.k}` }, ctx.col, "At step 0 a robot has "
      + "seen only where its teammates start: a 1.00 there is its prior, which takes the team "
      + "to be efficient (about 1 nat per metre of total travel, so a goal a few metres cheaper "
      + "is near-certain) and, at orders 2 and 3, predicts each teammate from the goals the "
      + "robot takes it to know of.");
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
      + "teammate's (dashed)");
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
    // Every line [values, robot, dashed, label], each drawn GAP px from the next (own lines
    // above, models below), so that lines with equal values lie side by side, not on top.
    const lines = [
      ...t.robots.map((r, i) => [own.map((s) => s[i]), i, false, `${r}'s own`]),
      ...t.robots.map((r, j) => [nested.map((s) => s[focus][j]), j, true,
        `${t.robots[focus]}'s model of ${r}'s`]).filter((l) => l[1] !== focus),
    ];
    const GAP = 2.5;
    lines.forEach(([series, i, dashed, name], q) => {
      const dy = (q - (lines.length - 1) / 2) * GAP;
      el("svg:polyline", { points: series.map((v, s) => `${cx(s)},${cy(v) + dy}`).join(" "),
        fill: "none", stroke: colour(i), "stroke-width": dashed ? 2.2 : 1.8,
        "stroke-dasharray": dashed ? "5 3" : "", class: dashed ? "nested" : "own",
        "data-offset": dy, "data-line": name }, chart);
    });
    const cursor = el("svg:line", { y1: 18, y2: H - padB, stroke: "#555" }, chart);
    const legend = el("div", { class: "legend sets-legend", id: `sets-legend-${k}` }, col);
    lines.forEach(([, i, dashed, name]) => {
      const entry = el("span", { "data-line": name }, legend);
      const sample = el("svg:svg", { width: 26, height: 8 }, entry);
      el("svg:line", { x1: 1, y1: 4, x2: 25, y2: 4, stroke: colour(i), "stroke-width": 2.2,
        "stroke-dasharray": dashed ? "5 3" : "" }, sample);
      entry.append(` ${name}`);
    });
    el("div", { class: "note" }, col, `Lines with equal values are drawn ${GAP} px apart `
      + "(own sets above, models below), so that a model equal to a teammate's own set shows "
      + "beside it rather than hidden under it.");

    const types = t.teammate_types || null;
    const kept = types ? t.robots.map((r, i) => i)
      .filter((i) => types.some((s) => s[i].some((row) => row.every((v) => v !== null)))) : [];
    const reader = kept.includes(focus) ? focus : kept[0];
    let reading = null;
    if (kept.length) {  // a table: teammates by behaviours of the library
      el("h3", {}, col, `How ${t.robots[reader]} reads its teammates' behaviour: its `
        + "posterior over a library of behaviours, from their moves (bold: the most likely)");
      reading = robotTable(col, { class: "reading", id: `reading-${k}` },
        { robots: t.robots, goals: t.types }, t.robots.map((r, j) => j).filter((j) => j !== reader));
      const meanings = ctx.p.type_meanings || {};
      const prior = ctx.p.type_prior ? " Before any move (the prior): " + t.types.map((name, q) =>
        `${name} ${ctx.p.type_prior[q].toFixed(2)}`).join(", ") + "." : "";
      el("div", { class: "note", id: `reading-key-${k}` }, col, t.types.map((name) =>
        `${name}: ${meanings[name] || name}`).join("; ") + "." + prior);
    }
    return (step) => {
      const decided = Math.min(step, t.steps - 1);
      cursor.setAttribute("x1", cx(Math.max(decided, 0)));
      cursor.setAttribute("x2", cx(Math.max(decided, 0)));
      if (reading) {
        const rows = t.robots.map((r, j) => j).filter((j) => j !== reader);
        reading.cells.forEach((cells, r) => {
          const row = types[Math.max(decided, 0)][reader][rows[r]];
          const top = row.some((v) => v === null) ? -1 : row.indexOf(Math.max(...row));
          cells.goals.forEach((cell, q) => {
            cell.textContent = row[q] === null ? "n/c" : row[q].toFixed(2);
            cell.className = "goal-cell" + (q === top ? " likeliest" : "")
              + (row[q] === null ? " not-computed" : "");
          });
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
      + "a teammate; wait: for helpers at a task), since which step, and over the trial (bars: "
      + "blue a task, darker for later tasks; grey explore; red fetch; amber wait)");
    const table = el("table", { class: "targets", id: `targets-${k}` }, ctx.col);
    const rows = t.robots.map((r, i) => {
      const tr = el("tr", { "data-robot": r }, table);
      el("th", { style: `color:${colour(i)}` }, tr, r);
      return [el("td", { class: "target" }, tr, ""), el("td", { class: "since" }, tr, "")];
    });
    const cursor = targetTimeline(ctx);
    return (step) => {
      const decided = Math.min(step, t.steps - 1);
      cursor(decided);
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

  // Each robot's targets over the trial: one row per robot, one bar per run of steps with
  // the same target (a task: blue, darker for later tasks, named; explore: pale; fetch: red;
  // wait: amber), and a cursor at the step shown (the function returned moves it).
  function targetTimeline(ctx) {
    const t = ctx.t, m = t.goals.length, W = 430, padL = 30, row = 16, top = 4;
    const H = top + row * t.robots.length + 18;
    const svg = el("svg:svg", { class: "targets-chart", id: `timeline-${ctx.k}`, width: W,
      height: H }, ctx.col);
    const x = (s) => padL + (s / Math.max(1, t.steps)) * (W - padL - 8);
    const fill = (v) => (v >= 0 ? `hsl(215, 45%, ${72 - (40 * v) / Math.max(1, m - 1)}%)`
      : { "-1": "#eeeeee", "-2": "#e07070", "-3": "#f0c060" }[v]);
    t.robots.forEach((r, i) => {
      const y = top + i * row;
      el("svg:text", { x: padL - 4, y: y + 11, "text-anchor": "end", "font-size": 11,
        fill: colour(i) }, svg, r);
      for (let a = 0; a < t.steps;) {
        const v = t.steer_to[a][i];
        let b = a;
        while (b + 1 < t.steps && t.steer_to[b + 1][i] === v) b++;
        el("svg:rect", { x: x(a), y: y, width: Math.max(x(b + 1) - x(a), 0.5), height: row - 3,
          fill: fill(v), class: "segment", "data-robot": r, "data-target": target(t, v),
          "data-from": a, "data-to": b }, svg);
        if (v >= 0 && x(b + 1) - x(a) > 22) {
          el("svg:text", { x: x(a) + 2, y: y + 10, "font-size": 9, fill: "#fff" }, svg,
            t.goals[v]);
        }
        a = b + 1;
      }
    });
    const xtick = tickStep(Math.max(t.steps, 1), 5);
    for (let s = 0; s <= t.steps; s += xtick) {
      el("svg:text", { x: x(s), y: H - 3, "text-anchor": "middle", "font-size": 10,
        class: "tick x" }, svg, String(s));
    }
    const cursor = el("svg:line", { y1: 0, y2: H - 14, stroke: "#000" }, svg);
    return (step) => {
      cursor.setAttribute("x1", x(Math.max(step, 0) + 0.5));
      cursor.setAttribute("x2", x(Math.max(step, 0) + 0.5));
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
    const t = ctx.t;
    const model = teammateTable(ctx, { class: "model tasks", id: `model-${ctx.k}` }, [],
      " knows that each teammate knows of (✓ since which step; · does not know it; amber: the "
      + "teammate does know of it)", (step) => draw(step));
    function draw(step) {
      const who = model.who, others = t.robots.map((r, j) => j).filter((j) => j !== who);
      model.table.cells.forEach((row, r) => row.goals.forEach((cell, g) => {
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

  return PANELS;
}
