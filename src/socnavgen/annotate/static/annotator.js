// socnavgen annotate: draw a scene graph over a map image. Plain JS, no build step.
// Model: graph = {nodes: [{id, type, pos: [x, y]}], links: [{source, target, type}]} in image pixels.
"use strict";
(() => {
  const ID_ALPHABET = "abcdefghijklmnopqrstuvwxyz0123456789"; // same as socnavgen.location.scene_graph
  // Colours come from the server (the palettes of location/render.py): a type looks the same here and in the PNG.
  const NODE_R = 7, HIT_R = 10, DRAG_PX = 4, HISTORY = 200;

  const $ = (id) => document.getElementById(id);
  const canvas = $("canvas"), ctx = canvas.getContext("2d");
  const st = {
    name: "", size: [1, 1], schema: {node_types: [], edge_types: []},
    graph: {nodes: [], links: []}, nodeType: null, edgeType: null, tool: "draw",
    view: {scale: 1, ox: 0, oy: 0}, selected: null, hover: null, warnings: [], highlight: null,
    undo: [], redo: [], dirty: false, drag: null, image: null,
    palette: {node: ["#888"], edge: ["#888"], unknown: "#FF00FF"}, typeChosen: false, description: "",
  };

  // ---------- helpers ----------
  const nodeById = (id) => st.graph.nodes.find((n) => n.id === id);
  const toScreen = (x, y) => [(x + 0.5) * st.view.scale + st.view.ox, (y + 0.5) * st.view.scale + st.view.oy];
  const toImage = (sx, sy) => [(sx - st.view.ox) / st.view.scale, (sy - st.view.oy) / st.view.scale];
  const paletteOf = (list) => (list === st.schema.edge_types ? st.palette.edge : st.palette.node);
  const colorOf = (list, type) => { const i = list.indexOf(type), p = paletteOf(list); return i < 0 ? st.palette.unknown : p[i % p.length]; };
  const sameEdge = (e, a, b) => (e.source === a && e.target === b) || (e.source === b && e.target === a);

  function newId() {
    const taken = new Set(st.graph.nodes.map((n) => n.id));
    if (taken.size >= ID_ALPHABET.length ** 2) throw new Error("all 1296 node ids are in use");
    const buf = new Uint32Array(2);
    for (;;) {
      crypto.getRandomValues(buf);
      const id = ID_ALPHABET[buf[0] % 36] + ID_ALPHABET[buf[1] % 36];
      if (!taken.has(id)) return id;
    }
  }

  function status(text, kind) { const s = $("status"); s.textContent = text; s.className = kind || ""; }

  // ---------- undo / redo: whole-state snapshots (graphs are small) ----------
  const snapshot = () => JSON.stringify({graph: st.graph, schema: st.schema});
  function restore(text) {
    const s = JSON.parse(text); st.graph = s.graph; st.schema = s.schema;
    if (!st.schema.node_types.includes(st.nodeType)) st.nodeType = st.schema.node_types[0] || null;
    if (!st.schema.edge_types.includes(st.edgeType)) st.edgeType = st.schema.edge_types[0] || null;
    if (st.selected && !stillExists(st.selected)) st.selected = null;
  }
  function stillExists(sel) {
    return sel.kind === "node" ? !!nodeById(sel.id) : st.graph.links.some((e) => sameEdge(e, sel.a, sel.b));
  }
  function change(fn) { // every edit goes through here so it can be undone
    const before = snapshot();
    fn();
    if (snapshot() === before) return;
    st.undo.push(before); if (st.undo.length > HISTORY) st.undo.shift();
    st.redo = []; markDirty(true); refresh();
  }
  function undo() { if (!st.undo.length) return; st.redo.push(snapshot()); restore(st.undo.pop()); markDirty(true); refresh(); }
  function redo() { if (!st.redo.length) return; st.undo.push(snapshot()); restore(st.redo.pop()); markDirty(true); refresh(); }
  function markDirty(d) { st.dirty = d; $("save").classList.toggle("dirty", d); }

  // ---------- edits ----------
  async function guessType(px, py) { // until the user picks a type, the map suggests one (DOORWAY, ROOM)
    const atClick = st.nodeType; // the type selected when the user clicked (a pick made meanwhile is for later clicks)
    if (st.typeChosen) return atClick;
    try {
      const {ok, data} = await post("/api/guess-type", {x: px, y: py, node_types: st.schema.node_types});
      return ok && data.type && st.schema.node_types.includes(data.type) ? data.type : atClick;
    } catch (e) { return atClick; }
  }
  async function addNode(x, y) {
    if (!st.nodeType) { status("add a node type first", "error"); return; }
    const px = Math.floor(x), py = Math.floor(y);
    if (px < 0 || py < 0 || px >= st.size[0] || py >= st.size[1]) return;
    const type = await guessType(px, py);
    let id; try { id = newId(); } catch (e) { status(e.message, "error"); return; }
    change(() => st.graph.nodes.push({id, type, pos: [px, py]}));
    st.selected = {kind: "node", id}; refresh();
  }
  function addEdge(a, b) {
    if (a === b || !st.edgeType) return;
    if (st.graph.links.some((e) => sameEdge(e, a, b))) { status(`${a} and ${b} are already joined`); return; }
    change(() => st.graph.links.push({source: a, target: b, type: st.edgeType}));
    st.selected = {kind: "edge", a, b}; refresh();
  }
  function deleteSelection(sel) {
    if (!sel) return;
    change(() => {
      if (sel.kind === "node") {
        st.graph.nodes = st.graph.nodes.filter((n) => n.id !== sel.id);
        st.graph.links = st.graph.links.filter((e) => e.source !== sel.id && e.target !== sel.id);
      } else {
        st.graph.links = st.graph.links.filter((e) => !sameEdge(e, sel.a, sel.b));
      }
    });
    st.selected = null; refresh();
  }

  // ---------- hit testing (screen pixels) ----------
  function nodeAt(sx, sy) {
    let best = null, bestD = HIT_R;
    for (const n of st.graph.nodes) {
      const [x, y] = toScreen(n.pos[0], n.pos[1]); const d = Math.hypot(x - sx, y - sy);
      if (d <= bestD) { best = n; bestD = d; }
    }
    return best;
  }
  function edgeAt(sx, sy) {
    let best = null, bestD = 6;
    const byId = new Map(st.graph.nodes.map((n) => [n.id, n]));
    for (const e of st.graph.links) {
      const a = byId.get(e.source), b = byId.get(e.target); if (!a || !b) continue;
      const [x1, y1] = toScreen(...a.pos), [x2, y2] = toScreen(...b.pos);
      const L2 = (x2 - x1) ** 2 + (y2 - y1) ** 2 || 1;
      const t = Math.max(0, Math.min(1, ((sx - x1) * (x2 - x1) + (sy - y1) * (y2 - y1)) / L2));
      const d = Math.hypot(sx - (x1 + t * (x2 - x1)), sy - (y1 + t * (y2 - y1)));
      if (d <= bestD) { best = e; bestD = d; }
    }
    return best;
  }

  // ---------- drawing ----------
  function resize() {
    const r = canvas.getBoundingClientRect(), dpr = window.devicePixelRatio || 1;
    canvas.width = Math.max(1, Math.round(r.width * dpr)); canvas.height = Math.max(1, Math.round(r.height * dpr));
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0); draw();
  }
  function fit() {
    const r = canvas.getBoundingClientRect();
    const scale = Math.min(r.width / st.size[0], r.height / st.size[1]) * 0.96;
    st.view = {scale, ox: (r.width - st.size[0] * scale) / 2, oy: (r.height - st.size[1] * scale) / 2}; draw();
  }
  function zoomAt(sx, sy, factor) {
    const s = Math.min(80, Math.max(0.05, st.view.scale * factor)); const [ix, iy] = toImage(sx, sy);
    st.view = {scale: s, ox: sx - ix * s, oy: sy - iy * s}; draw();
  }
  function isWarned(kind, a, b) {
    return st.warnings.some((w) => (kind === "node" ? (w.nodes || []).includes(a) && !w.edge
      : w.edge && ((w.edge[0] === a && w.edge[1] === b) || (w.edge[0] === b && w.edge[1] === a))));
  }
  function draw() {
    const r = canvas.getBoundingClientRect();
    ctx.clearRect(0, 0, r.width, r.height);
    if (st.image) {
      ctx.imageSmoothingEnabled = st.view.scale < 1;
      ctx.drawImage(st.image, st.view.ox, st.view.oy, st.size[0] * st.view.scale, st.size[1] * st.view.scale);
    }
    const sel = st.selected, byId = new Map(st.graph.nodes.map((n) => [n.id, n])); // O(1) lookups on big graphs
    for (const e of st.graph.links) {
      const a = byId.get(e.source), b = byId.get(e.target); if (!a || !b) continue;
      const [x1, y1] = toScreen(...a.pos), [x2, y2] = toScreen(...b.pos);
      const chosen = sel && sel.kind === "edge" && sameEdge(e, sel.a, sel.b);
      if (chosen) line(x1, y1, x2, y2, "#ffeb3b", 10);
      if (isWarned("edge", e.source, e.target)) line(x1, y1, x2, y2, "#ff1744", 7, [6, 4]);
      line(x1, y1, x2, y2, colorOf(st.schema.edge_types, e.type), 3);
    }
    const d = st.drag;
    if (d && d.mode === "edge" && d.moved) {
      const a = nodeById(d.from); const [x1, y1] = toScreen(...a.pos);
      line(x1, y1, d.sx, d.sy, colorOf(st.schema.edge_types, st.edgeType), 2, [5, 4]);
    }
    ctx.font = "bold 12px system-ui, sans-serif"; ctx.textBaseline = "middle";
    for (const n of st.graph.nodes) {
      const [x, y] = toScreen(...n.pos);
      if (isWarned("node", n.id)) ring(x, y, NODE_R + 5, "#ff1744", 3);
      if (sel && sel.kind === "node" && sel.id === n.id) ring(x, y, NODE_R + 3, "#ffeb3b", 4);
      ctx.beginPath(); ctx.arc(x, y, NODE_R, 0, 2 * Math.PI);
      ctx.fillStyle = colorOf(st.schema.node_types, n.type); ctx.fill();
      ctx.lineWidth = 1.5; ctx.strokeStyle = "#111"; ctx.stroke();
      ctx.lineWidth = 3; ctx.strokeStyle = "#fff"; ctx.strokeText(n.id, x + NODE_R + 3, y - NODE_R);
      ctx.fillStyle = "#111"; ctx.fillText(n.id, x + NODE_R + 3, y - NODE_R);
    }
  }
  function line(x1, y1, x2, y2, color, width, dash) {
    ctx.beginPath(); ctx.setLineDash(dash || []); ctx.moveTo(x1, y1); ctx.lineTo(x2, y2);
    ctx.strokeStyle = color; ctx.lineWidth = width; ctx.stroke(); ctx.setLineDash([]);
  }
  function ring(x, y, r, color, width) {
    ctx.beginPath(); ctx.arc(x, y, r, 0, 2 * Math.PI); ctx.strokeStyle = color; ctx.lineWidth = width; ctx.stroke();
  }

  // ---------- side panel ----------
  function el(tag, attrs, ...kids) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (k.startsWith("on")) e.addEventListener(k.slice(2), v); else if (v !== false) e.setAttribute(k, v === true ? "" : v);
    }
    for (const k of kids) e.append(k); // text nodes only: type names are user text, never HTML
    return e;
  }
  function renderTypes(listId, kind) {
    const key = kind === "node" ? "node_types" : "edge_types", current = kind === "node" ? st.nodeType : st.edgeType;
    const used = new Set((kind === "node" ? st.graph.nodes : st.graph.links).map((x) => x.type));
    const ul = $(listId); ul.replaceChildren();
    st.schema[key].forEach((t, i) => {
      const radio = el("input", {type: "radio", name: `${kind}-type`, value: t, checked: t === current,
        "data-type": t, onchange: () => { if (kind === "node") { st.nodeType = t; st.typeChosen = true; } else st.edgeType = t; refresh(); }});
      const sw = el("span", {class: kind === "edge" ? "swatch line" : "swatch"});
      sw.style.background = colorOf(st.schema[key], t); // CSSOM, not a style attribute: the CSP forbids inline styles
      const label = el("label", {}, radio, " ", sw, " ", t + (i < 9 && kind === "node" ? `  (${i + 1})` : ""));
      const del = el("button", {title: used.has(t) ? "in use: saving will be refused until no item has this type"
        : "remove this type", onclick: () => change(() => { st.schema[key] = st.schema[key].filter((x) => x !== t); restore(snapshot()); })}, "\u00d7");
      ul.append(el("li", {}, label, del));
    });
  }
  function addType(kind, name) {
    name = name.trim(); const key = kind === "node" ? "node_types" : "edge_types";
    if (!name || name.length > 64 || /[\x00-\x1f\x7f]/.test(name)) { status("a type name is 1-64 printable characters", "error"); return; }
    if (st.schema[key].includes(name)) { status(`${name} already exists`); return; }
    change(() => { st.schema[key].push(name); if (kind === "node") st.nodeType = name; else st.edgeType = name; });
  }
  function renderSelection() {
    const box = $("selection"), sel = st.selected; box.replaceChildren();
    if (!sel) { box.append("nothing selected"); return; }
    const item = sel.kind === "node" ? nodeById(sel.id) : st.graph.links.find((e) => sameEdge(e, sel.a, sel.b));
    if (!item) { box.append("nothing selected"); return; }
    const types = sel.kind === "node" ? st.schema.node_types : st.schema.edge_types;
    const select = el("select", {id: "selection-type", onchange: (ev) => change(() => { item.type = ev.target.value; })});
    for (const t of new Set([...types, item.type])) select.append(el("option", {value: t, selected: t === item.type}, t));
    const title = sel.kind === "node" ? `node ${item.id} at (${item.pos[0]}, ${item.pos[1]})` : `edge ${item.source} \u2013 ${item.target}`;
    box.append(el("div", {id: "selection-title"}, title), select, " ",
      el("button", {onclick: () => deleteSelection(sel)}, "Delete"));
  }
  function renderWarnings() {
    const ul = $("warnings"); ul.replaceChildren();
    $("warning-count").textContent = st.warnings.length ? `(${st.warnings.length})` : "";
    if (!st.warnings.length) { ul.append(el("li", {class: "ok"}, "no problems found")); return; }
    for (const w of st.warnings) {
      ul.append(el("li", {class: w.severity === "error" ? "error" : "", title: w.hint || "", onclick: () => focusOn(w)}, w.message));
    }
  }
  function focusOn(w) {
    const n = (w.nodes || []).map(nodeById).filter(Boolean); if (!n.length) return;
    const x = n.reduce((s, a) => s + a.pos[0], 0) / n.length, y = n.reduce((s, a) => s + a.pos[1], 0) / n.length;
    const r = canvas.getBoundingClientRect(), [sx, sy] = toScreen(x, y);
    st.view.ox += r.width / 2 - sx; st.view.oy += r.height / 2 - sy;
    st.selected = w.edge ? {kind: "edge", a: w.edge[0], b: w.edge[1]} : {kind: "node", id: n[0].id}; refresh();
  }
  function refresh() {
    renderTypes("node-types", "node"); renderTypes("edge-types", "edge"); renderSelection(); renderWarnings();
    $("undo").disabled = !st.undo.length; $("redo").disabled = !st.redo.length;
    $("counts").textContent = `${st.graph.nodes.length} nodes, ${st.graph.links.length} edges`;
    draw();
  }

  // ---------- mouse ----------
  function pointer(ev) { const r = canvas.getBoundingClientRect(); return [ev.clientX - r.left, ev.clientY - r.top]; }
  canvas.addEventListener("mousedown", (ev) => {
    canvas.focus();
    const [sx, sy] = pointer(ev), node = nodeAt(sx, sy);
    const base = {x0: sx, y0: sy, sx, sy, moved: false};
    if (ev.button === 1 || ev.button === 2) { st.drag = {...base, mode: "pan", view: {...st.view}}; ev.preventDefault(); return; }
    if (ev.button !== 0) return;
    if (node && (st.tool === "move" || ev.shiftKey)) st.drag = {...base, mode: "move", id: node.id, before: snapshot()};
    else if (node && st.tool === "draw") st.drag = {...base, mode: "edge", from: node.id};
    else if (node) st.drag = {...base, mode: "click", node: node.id};
    else st.drag = {...base, mode: "pan-or-click", view: {...st.view}};
  });
  window.addEventListener("mousemove", (ev) => {
    const [sx, sy] = pointer(ev), [ix, iy] = toImage(sx, sy);
    $("coords").textContent = ix >= 0 && iy >= 0 && ix < st.size[0] && iy < st.size[1] ? `x ${Math.floor(ix)}  y ${Math.floor(iy)}` : "";
    const d = st.drag; if (!d) return;
    d.sx = sx; d.sy = sy;
    if (Math.hypot(sx - d.x0, sy - d.y0) > DRAG_PX) d.moved = true;
    if (!d.moved) return;
    if (d.mode === "pan" || d.mode === "pan-or-click") {
      st.view.ox = d.view.ox + sx - d.x0; st.view.oy = d.view.oy + sy - d.y0;
    } else if (d.mode === "move") {
      const n = nodeById(d.id); if (n) n.pos = [Math.min(st.size[0] - 1, Math.max(0, Math.floor(ix))), Math.min(st.size[1] - 1, Math.max(0, Math.floor(iy)))];
    }
    draw();
  });
  window.addEventListener("mouseup", (ev) => {
    const d = st.drag; st.drag = null; if (!d) return;
    const [sx, sy] = pointer(ev);
    if (d.mode === "move") {
      if (d.moved && d.before !== snapshot()) { st.undo.push(d.before); st.redo = []; markDirty(true); }
      st.selected = {kind: "node", id: d.id};
    } else if (d.mode === "edge") {
      const target = nodeAt(sx, sy);
      if (d.moved && target && target.id !== d.from) addEdge(d.from, target.id);
      else if (!d.moved) st.selected = {kind: "node", id: d.from};
    } else if (d.mode === "click") {
      if (!d.moved) { if (st.tool === "delete") deleteSelection({kind: "node", id: d.node}); else st.selected = {kind: "node", id: d.node}; }
    } else if (d.mode === "pan-or-click" && !d.moved) {
      const e = edgeAt(sx, sy);
      if (e) {
        const sel = {kind: "edge", a: e.source, b: e.target};
        if (st.tool === "delete") deleteSelection(sel); else st.selected = sel;
      } else if (st.tool === "draw") addNode(...toImage(sx, sy));
      else st.selected = null;
    }
    refresh();
  });
  canvas.addEventListener("contextmenu", (ev) => ev.preventDefault());
  canvas.addEventListener("wheel", (ev) => { ev.preventDefault(); const [sx, sy] = pointer(ev); zoomAt(sx, sy, Math.exp(-ev.deltaY * 0.0015)); }, {passive: false});

  // ---------- keyboard ----------
  window.addEventListener("keydown", (ev) => {
    if (ev.target instanceof HTMLInputElement || ev.target instanceof HTMLSelectElement) return;
    const k = ev.key.toLowerCase(), mod = ev.ctrlKey || ev.metaKey;
    if (mod && k === "z" && !ev.shiftKey) { undo(); ev.preventDefault(); }
    else if (mod && (k === "y" || (k === "z" && ev.shiftKey))) { redo(); ev.preventDefault(); }
    else if (mod && k === "s") { save(); ev.preventDefault(); }
    else if (k === "delete" || k === "backspace") { deleteSelection(st.selected); ev.preventDefault(); }
    else if (!mod && (k === "a" || k === "m" || k === "d")) setTool({a: "draw", m: "move", d: "delete"}[k]);
    else if (!mod && k === "f") fit();
    else if (!mod && k === "escape") { st.selected = null; refresh(); }
    else if (!mod && /^[1-9]$/.test(k) && st.schema.node_types[+k - 1]) { st.nodeType = st.schema.node_types[+k - 1]; st.typeChosen = true; refresh(); }
  });
  function setTool(t) {
    st.tool = t; for (const r of document.querySelectorAll("input[name=tool]")) r.checked = r.value === t;
    canvas.style.cursor = t === "move" ? "move" : t === "delete" ? "not-allowed" : "crosshair";
  }
  for (const r of document.querySelectorAll("input[name=tool]")) r.addEventListener("change", () => setTool(r.value));

  // ---------- server ----------
  const payload = () => ({nodes: st.graph.nodes, links: st.graph.links, schema: st.schema});
  async function post(url, body) {
    const res = await fetch(url, {method: "POST", headers: {"Content-Type": "application/json"}, body: JSON.stringify(body)});
    let data = {}; try { data = await res.json(); } catch (e) { data = {error: `HTTP ${res.status}`}; }
    return {ok: res.ok, data};
  }
  async function save() {
    status("saving\u2026");
    try {
      const {ok, data} = await post("/api/save", payload());
      if (!ok) {
        st.warnings = (data.problems || []).map((p) => ({message: p, severity: "error", nodes: [], edge: null}));
        status(`${data.error || "save failed"}${data.problems && data.problems.length ? ": " + data.problems[0] : ""} (previous files kept)`, "error");
      } else {
        st.warnings = data.warnings || []; markDirty(false);
        const errors = st.warnings.filter((w) => w.severity === "error").length; // the levels of `location check`
        status(`saved ${data.nodes} nodes, ${data.links} edges to ${data.saved.join(", ")}` +
          (errors ? ` \u2014 but location check finds ${errors} error(s): see the list` : ""), errors ? "error" : "ok");
      }
    } catch (e) { status(`save failed: ${e.message} (previous files kept)`, "error"); }
    refresh();
  }
  async function check() {
    status("checking\u2026");
    try {
      const {ok, data} = await post("/api/check", payload());
      if (!ok) { status(data.error || "check failed", "error"); return; }
      st.warnings = data.warnings || []; status(`check: ${st.warnings.length} problem(s)`, st.warnings.length ? "" : "ok");
    } catch (e) { status(`check failed: ${e.message}`, "error"); }
    refresh();
  }
  async function replaceMap(file) {
    if (file.size > 16 * 1024 * 1024) { status("the map image is larger than 16 MB", "error"); return; }
    const type = /\.pgm$/i.test(file.name) ? "image/x-portable-graymap" : (file.type || "application/octet-stream");
    status("uploading the map\u2026");
    try {
      const res = await fetch("/api/map", {method: "POST", headers: {"Content-Type": type}, body: await file.arrayBuffer()});
      const data = await res.json();
      if (!res.ok) { status(`${data.error}: ${(data.problems || []).join("; ")}`, "error"); return; }
      st.warnings = data.warnings || [];
      const img = new Image();
      img.onload = () => { st.image = img; refresh(); status(`map replaced (previous kept as ${data.replaced}.bak)`, "ok"); };
      img.src = `/api/map?v=${Date.now()}`;
    } catch (e) { status(`upload failed: ${e.message}`, "error"); }
  }
  async function load() {
    const res = await fetch("/api/location"); const data = await res.json();
    if (!res.ok) { status(data.error || "cannot load the location", "error"); return; }
    st.name = data.name; st.size = data.image_size; st.schema = data.schema; st.graph = data.graph;
    st.warnings = data.warnings || []; st.edgeType = st.schema.edge_types[0];
    st.palette = data.palette || st.palette; st.description = data.description || "";
    st.nodeType = st.schema.node_types.includes(data.default_node_type) ? data.default_node_type : st.schema.node_types[0];
    $("description").value = st.description;
    $("location-name").textContent = `\u2014 ${data.name} (${st.size[0]}\u00d7${st.size[1]} px)`;
    document.title = `annotate ${data.name}`;
    const img = new Image();
    img.onload = () => { st.image = img; fit(); refresh(); status("ready", "ok"); document.body.dataset.ready = "1"; };
    img.onerror = () => status("cannot load the map image", "error");
    img.src = "/api/map";
    resize(); fit(); refresh();
  }

  async function suggest() {
    if (st.graph.nodes.length && !confirm("Replace the current graph by a suggested one? (Undo brings it back)")) return;
    status("extracting a graph from the map\u2026");
    try {
      const {ok, data} = await post("/api/suggest", payload());
      if (!ok) { status(data.error || "suggestion failed", "error"); return; }
      change(() => { st.graph = data.graph; st.schema = data.schema; });
      status(`suggested: ${data.summary}; edit it, then save`, "ok");
    } catch (e) { status(`suggestion failed: ${e.message}`, "error"); }
  }
  async function saveDescription(ev) {
    ev.preventDefault();
    try {
      const {ok, data} = await post("/api/description", {description: $("description").value});
      if (!ok) { status(`${data.error}: ${(data.problems || []).join("; ")}`, "error"); return; }
      st.description = data.description; status("description saved to location.yaml", "ok");
    } catch (e) { status(`description not saved: ${e.message}`, "error"); }
  }

  $("suggest").addEventListener("click", suggest);
  $("description-form").addEventListener("submit", saveDescription);
  $("replace-map").addEventListener("click", () => $("map-file").click());
  $("map-file").addEventListener("change", (ev) => { const f = ev.target.files[0]; ev.target.value = ""; if (f) replaceMap(f); });
  $("undo").addEventListener("click", undo); $("redo").addEventListener("click", redo);
  $("fit").addEventListener("click", fit); $("save").addEventListener("click", save); $("check").addEventListener("click", check);
  $("add-node-type").addEventListener("submit", (ev) => { ev.preventDefault(); addType("node", ev.target.name.value); ev.target.reset(); });
  $("add-edge-type").addEventListener("submit", (ev) => { ev.preventDefault(); addType("edge", ev.target.name.value); ev.target.reset(); });
  window.addEventListener("resize", resize);
  window.addEventListener("beforeunload", (ev) => { if (st.dirty) { ev.preventDefault(); ev.returnValue = ""; } });

  // A small read-only handle for tests and power users: coordinates, never a way around the UI.
  window.annotator = {
    imageToClient(x, y) { const r = canvas.getBoundingClientRect(), [sx, sy] = toScreen(x, y); return [sx + r.left, sy + r.top]; },
    state() { return JSON.parse(JSON.stringify({graph: st.graph, schema: st.schema, dirty: st.dirty, view: st.view})); },
  };
  load().catch((e) => status(`cannot load: ${e.message}`, "error"));
})();
