// epistemica model view: the worlds, each agent's relations, the designated worlds of one
// Kripke model (format epistemica-kripke-1), the spec's claims with their truth sets as
// epistemica computed them, and a formula box that evaluates the static language
// (propositional connectives, K, B, Kw, M, E, C, D, EB, CB) in the page.
// window.epistemicaModel = { evaluate(text) -> { worlds: [...], designated: bool } }.
"use strict";
(function () {
  const page = JSON.parse(document.getElementById("data").textContent);
  const model = page.model, worlds = model.worlds, W = worlds.length;
  const index = new Map(worlds.map((w, i) => [w.name, i]));
  const canon = (s) => s.replace(/\s+/g, "");
  const atoms = new Set(model.atoms.map(canon));
  const valuation = worlds.map((w) => new Set(w.atoms.map(canon)));

  // Successor lists per agent and kind ("knowledge" falls back to "belief").
  function successors(spec) {
    const out = Array.from({ length: W }, () => []);
    if (spec.blocks) {
      for (const block of spec.blocks) {
        const members = block.map((name) => index.get(name)).filter((i) => i !== undefined);
        for (const w of members) out[w] = members;
      }
    } else {
      for (const [a, b] of spec.arrows || []) {
        if (index.has(a) && index.has(b)) out[index.get(a)].push(index.get(b));
      }
    }
    return out;
  }
  const rel = {};
  for (const agent of model.agents) {
    const entry = model.relations[agent] || {};
    const belief = successors(entry.belief || { arrows: [] });
    rel[agent] = { belief, knowledge: entry.knowledge ? successors(entry.knowledge) : belief };
  }

  // Tokens and a recursive-descent parser with the precedence of epistemica's grammar:
  // unary < & < | < -> (right) < <-> (left).
  const TOKEN = /\s*(<->|<=>|↔|->|=>|→|&&|&|∧|\|\||\||∨|~|!|¬|\(|\)|\[|\]|,|[A-Za-z_][A-Za-z0-9_]*|\d+|⊤|⊥|\S)/gy;
  const WORDS = { and: "&", or: "|", not: "~", true: "⊤", false: "⊥" };
  const ALIAS = { "&&": "&", "∧": "&", "||": "|", "∨": "|", "!": "~", "¬": "~", "=>": "->",
    "→": "->", "<=>": "<->", "↔": "<->" };
  const MODAL = new Set(["K", "B", "Kw", "M"]), GROUP = new Set(["E", "C", "D", "EB", "CB"]);

  function tokenize(text) {
    const out = [];
    TOKEN.lastIndex = 0;
    let match;
    while (TOKEN.lastIndex < text.length && (match = TOKEN.exec(text))) {
      const tok = match[1];
      out.push(ALIAS[tok] || WORDS[tok] || tok);
    }
    if (text.slice(TOKEN.lastIndex).trim()) throw new Error("cannot read the formula");
    return out;
  }

  function parse(text) {
    const toks = tokenize(text);
    let pos = 0;
    const peek = () => toks[pos], next = () => toks[pos++];
    const expect = (tok) => {
      if (toks[pos] !== tok) throw new Error(`expected '${tok}' at token ${pos + 1}, got '${toks[pos] ?? "end"}'`);
      pos++;
    };
    const name = () => {
      const tok = next();
      if (!tok || !/^[A-Za-z_0-9]/.test(tok)) throw new Error(`expected a name, got '${tok ?? "end"}'`);
      return tok;
    };
    function iff() {
      let left = implies();
      while (peek() === "<->") { next(); left = { op: "<->", a: left, b: implies() }; }
      return left;
    }
    function implies() {
      const left = disj();
      if (peek() === "->") { next(); return { op: "->", a: left, b: implies() }; }
      return left;
    }
    function disj() {
      let left = conj();
      while (peek() === "|") { next(); left = { op: "|", a: left, b: conj() }; }
      return left;
    }
    function conj() {
      let left = unary();
      while (peek() === "&") { next(); left = { op: "&", a: left, b: unary() }; }
      return left;
    }
    function unary() {
      const tok = peek();
      if (tok === "~") { next(); return { op: "~", a: unary() }; }
      if ((MODAL.has(tok) || GROUP.has(tok)) && toks[pos + 1] === "[") {
        next(); next();
        const agents = [name()];
        while (peek() === ",") { next(); agents.push(name()); }
        expect("]");
        if (MODAL.has(tok) && agents.length !== 1) throw new Error(`${tok}[...] takes one agent`);
        for (const a of agents) if (!rel[a]) throw new Error(`unknown agent '${a}'; agents: ${model.agents.join(", ")}`);
        return { op: tok, agents, a: unary() };
      }
      if (tok === "[" || tok === "<") throw new Error("announcements and actions are not evaluated in the page: use 'epistemica check --formula'");
      return primary();
    }
    function primary() {
      const tok = next();
      if (tok === "(") { const f = iff(); expect(")"); return f; }
      if (tok === "⊤") return { op: "top" };
      if (tok === "⊥") return { op: "bottom" };
      if (!tok || !/^[A-Za-z_]/.test(tok)) throw new Error(`expected a formula, got '${tok ?? "end"}'`);
      let atom = tok;
      if (peek() === "(") {
        next();
        const args = [name()];
        while (peek() === ",") { next(); args.push(name()); }
        expect(")");
        atom += `(${args.join(",")})`;
      }
      if (!atoms.has(atom)) throw new Error(`unknown atom '${atom}'`);
      return { op: "atom", atom };
    }
    const formula = iff();
    if (pos < toks.length) throw new Error(`unexpected '${toks[pos]}' at token ${pos + 1}`);
    return formula;
  }

  const box = (succ, truth) => succ.map((next) => next.every((v) => truth[v]));
  function closure(agents, kind, truth) {
    // C[G] f: f at every world reachable in one or more steps of G's relations.
    return worlds.map((_, w) => {
      const seen = new Set(), stack = [w];
      while (stack.length) {
        const u = stack.pop();
        for (const a of agents) for (const v of rel[a][kind][u]) {
          if (!seen.has(v)) { seen.add(v); stack.push(v); }
        }
      }
      return [...seen].every((v) => truth[v]);
    });
  }
  function truth(f) {
    switch (f.op) {
      case "top": return worlds.map(() => true);
      case "bottom": return worlds.map(() => false);
      case "atom": return valuation.map((set) => set.has(f.atom));
      case "~": return truth(f.a).map((v) => !v);
      case "&": { const a = truth(f.a), b = truth(f.b); return a.map((v, i) => v && b[i]); }
      case "|": { const a = truth(f.a), b = truth(f.b); return a.map((v, i) => v || b[i]); }
      case "->": { const a = truth(f.a), b = truth(f.b); return a.map((v, i) => !v || b[i]); }
      case "<->": { const a = truth(f.a), b = truth(f.b); return a.map((v, i) => v === b[i]); }
      case "K": return box(rel[f.agents[0]].knowledge, truth(f.a));
      case "B": return box(rel[f.agents[0]].belief, truth(f.a));
      case "M": { const no = truth(f.a).map((v) => !v);
        return box(rel[f.agents[0]].knowledge, no).map((v) => !v); }
      case "Kw": { const a = truth(f.a), k = rel[f.agents[0]].knowledge;
        const yes = box(k, a), no = box(k, a.map((v) => !v));
        return yes.map((v, i) => v || no[i]); }
      case "E": case "EB": { const a = truth(f.a), kind = f.op === "E" ? "knowledge" : "belief";
        return worlds.map((_, w) => f.agents.every((g) => rel[g][kind][w].every((v) => a[v]))); }
      case "C": case "CB":
        return closure(f.agents, f.op === "C" ? "knowledge" : "belief", truth(f.a));
      case "D": { const a = truth(f.a);
        return worlds.map((_, w) => {
          let common = rel[f.agents[0]].knowledge[w];
          for (const g of f.agents.slice(1)) {
            const other = new Set(rel[g].knowledge[w]);
            common = common.filter((v) => other.has(v));
          }
          return common.every((v) => a[v]);
        }); }
      default: throw new Error(`cannot evaluate '${f.op}'`);
    }
  }
  const designated = model.designated.map((name) => index.get(name));
  function evaluate(text) {
    const values = truth(parse(text));
    return { worlds: worlds.filter((_, i) => values[i]).map((w) => w.name),
      designated: designated.every((i) => values[i]) };
  }

  // The page.
  const app = document.getElementById("app");
  const el = (tag, attrs, parent, text) => {
    const node = tag.startsWith("svg:")
      ? document.createElementNS("http://www.w3.org/2000/svg", tag.slice(4))
      : document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) node.setAttribute(k, v);
    if (text !== undefined) node.textContent = text;
    if (parent) parent.appendChild(node);
    return node;
  };
  const truncated = model.truncated ? ` (the first ${W} of ${model.n_worlds})` : "";
  el("p", {}, app, `${W} worlds${truncated}; agents ${model.agents.join(", ")}; atoms `
    + `${model.atoms.join(", ") || "(none)"}; designated: ${model.designated.join(", ")}`);

  const form = el("div", { class: "controls" }, app);
  el("label", { for: "formula" }, form, "Formula");
  const input = el("input", { id: "formula", type: "text", value: page.example || "",
    placeholder: "e.g. K[a] p | ~B[b] q" }, form);
  const button = el("button", { id: "evaluate", type: "button" }, form, "Evaluate");
  const result = el("div", { id: "result" }, app);
  el("div", { class: "note" }, app, "The box evaluates ~ & | -> <-> K B Kw M E C D EB CB "
    + "at every world of this model; announcements and actions need 'epistemica check'.");

  const row = el("div", { class: "row" }, app);
  const left = el("div", { class: "panel" }, row), right = el("div", { class: "panel" }, row);
  el("h2", {}, left, "Worlds (bold: designated)");
  const table = el("table", { id: "worlds" }, left);
  const head = el("tr", {}, table);
  ["world", "true atoms", "formula"].forEach((h) => el("th", {}, head, h));
  const marks = worlds.map((w, i) => {
    const tr = el("tr", { class: designated.includes(i) ? "designated" : "" }, table);
    el("td", {}, tr, w.name);
    el("td", {}, tr, w.atoms.join(", "));
    return el("td", { class: "mark" }, tr, "");
  });

  el("h2", {}, right, "Relations per agent");
  // Agents take the robots' palette (epistemica.sim.study.palette.ROBOT_COLOURS).
  const palette = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b",
    "#e377c2", "#17becf", "#bcbd22"];
  for (const [k, agent] of model.agents.entries()) {
    const entry = model.relations[agent] || {};
    for (const kind of ["knowledge", "belief"]) {
      const spec = entry[kind];
      if (!spec) continue;
      const title = el("div", { class: "relation", "data-agent": agent }, right);
      el("span", { class: "swatch", style: `background:${palette[k % palette.length]}` }, title);
      const items = spec.blocks ? spec.blocks.map((b) => `{${b.join(", ")}}`)
        : (spec.arrows || []).map(([a, b]) => `${a}→${b}`);
      const what = spec.blocks ? "classes" : "arrows";
      title.appendChild(document.createTextNode(
        `${agent}, ${kind}${entry.knowledge ? "" : " (= knowledge)"}: ${what} ${items.join(" ")}`));
    }
  }

  if (W <= 60) {
    // Worlds on a circle; one colour per agent; reflexive arrows left out.
    el("h2", {}, right, "Graph");
    const S = 420, R = 165, c = S / 2;
    const svg = el("svg:svg", { id: "graph", width: S, height: S }, right);
    const at = (i) => [c + R * Math.cos((2 * Math.PI * i) / W - Math.PI / 2),
      c + R * Math.sin((2 * Math.PI * i) / W - Math.PI / 2)];
    model.agents.forEach((agent, k) => {
      const succ = rel[agent].belief, off = (k - (model.agents.length - 1) / 2) * 3;
      succ.forEach((next, u) => next.forEach((v) => {
        if (u >= v && succ[v].includes(u)) return;
        if (u === v) return;
        const [x1, y1] = at(u), [x2, y2] = at(v);
        el("svg:line", { x1: x1 + off, y1: y1 + off, x2: x2 + off, y2: y2 + off,
          stroke: palette[k % palette.length], "stroke-width": 1.6, class: "edge",
          "data-agent": agent }, svg);
      }));
    });
    worlds.forEach((w, i) => {
      const [x, y] = at(i);
      el("svg:circle", { cx: x, cy: y, r: 15, fill: "#fff", stroke: "#000",
        "stroke-width": designated.includes(i) ? 3.5 : 1, class: "world" }, svg);
      el("svg:text", { x, y: y + 4, "text-anchor": "middle", "font-size": 11 }, svg, w.name);
    });
  }

  if (page.claims && page.claims.length) {
    el("h2", {}, app, "The spec's claims (truth sets computed by epistemica)");
    const claims = el("table", { id: "claims" }, app);
    const h = el("tr", {}, claims);
    ["claim", "formula", "expected", "holds", "worlds where it holds"].forEach((x) => el("th", {}, h, x));
    for (const c of page.claims) {
      const tr = el("tr", { class: c.expected === c.holds ? "holds" : "fails" }, claims);
      [c.name, c.formula, String(c.expected), String(c.holds), c.worlds.join(", ")]
        .forEach((x) => el("td", {}, tr, x));
    }
  }

  function show() {
    try {
      const out = evaluate(input.value);
      const set = new Set(out.worlds);
      marks.forEach((cell, i) => {
        const yes = set.has(worlds[i].name);
        cell.textContent = yes ? "true" : "false";
        cell.className = `mark ${yes ? "holds" : "fails"}`;
      });
      result.className = "";
      result.textContent = `${out.designated ? "holds" : "does not hold"} at the designated `
        + `worlds; true at ${out.worlds.length} of ${W}: ${out.worlds.join(", ")}`;
    } catch (err) {
      marks.forEach((cell) => { cell.textContent = ""; cell.className = "mark"; });
      result.className = "error";
      result.textContent = `error: ${err.message}`;
    }
  }
  button.addEventListener("click", show);
  input.addEventListener("keydown", (e) => { if (e.key === "Enter") show(); });
  window.epistemicaModel = { evaluate, show };
  if (input.value) show();
})();
