// sar-tree studio: the page. Plain JavaScript, no library, no network beyond this server.
// The server sends "hello" (tree SVG, map, timeline) and "frame" documents over /ws;
// this colours the tree's nodes, moves the robot, fills the blackboard and the reasons,
// and (replay) drives the timeline by sending "seek" (and the event list, events.js).
"use strict";

const SVGNS = "http://www.w3.org/2000/svg";
const params = new URLSearchParams(location.search);
const studio = {
  token: params.get("token"),   // needed for what writes (hot reload: /api/reload)
  ws: null, hello: null, frame: null, mode: null,
  nodes: new Map(),             // uid -> SVG <g>
  colours: {}, selected: null,
  t: 0, playing: false, speed: 1, seekPending: false, seekWanted: null, lastStep: 0,
  framesSeen: 0, drawnParts: {},
};
window.studio = studio;          // the browser tests read it

const $ = (id) => document.getElementById(id);

function connect() {
  const ws = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws`);
  studio.ws = ws;
  ws.onmessage = (e) => {
    const msg = JSON.parse(e.data);
    if (msg.type === "hello") onHello(msg);
    else if (msg.type === "frame") onFrame(msg);
    else if (msg.type === "node") showNode(msg);
    else if (msg.type === "checked") window.onChecked(msg);
    else if (msg.type === "error") notice(`refused: ${msg.message}`);
  };
  ws.onclose = () => { notice("disconnected from the studio server"); };
}

function send(msg) {
  if (studio.ws && studio.ws.readyState === WebSocket.OPEN) studio.ws.send(JSON.stringify(msg));
}

function notice(text) { $("notice").textContent = text; }

// ---------------------------------------------------------------- hello: tree, map, timeline
function onHello(msg) {
  studio.hello = msg;
  studio.mode = msg.mode;
  $("mode").textContent = msg.mode;
  $("title").textContent = msg.title;
  if (msg.tree) drawTree(msg.tree);
  drawWorld(msg.world);
  if (msg.mode === "replay") setupTimeline(msg.timeline);
  if (msg.edit) window.startEditor(msg.edit, msg.mode);  // live: the mission's tree file
}

function uidOf(title) {  // Graphviz name "n0_1_3" -> uid "0.1.3"
  return /^n[0-9_]+$/.test(title) ? title.slice(1).replace(/_/g, ".") : null;
}

function drawTree(tree) {
  studio.colours = tree.colours;
  const legend = $("legend");
  legend.innerHTML = "";
  for (const [status, colour] of Object.entries(tree.colours)) {
    const key = document.createElement("span");
    key.className = "key";
    key.style.background = colour;
    key.textContent = status;
    legend.appendChild(key);
  }
  const box = $("tree");
  box.innerHTML = tree.svg;
  studio.nodes.clear();
  for (const g of box.querySelectorAll("g.node")) {
    const title = g.querySelector("title");
    const uid = title && uidOf(title.textContent.trim());
    if (uid === null) continue;
    g.dataset.uid = uid;
    studio.nodes.set(uid, g);
    g.addEventListener("click", () => selectNode(uid));
  }
  if (studio.frame) paintTree(studio.frame);
}

function shapesOf(g) {
  // the node's own shapes (Graphviz nests them in <g><a> when the node has a tooltip)
  return [...g.querySelectorAll("polygon, ellipse, path")]
    .filter((s) => s.getAttribute("fill") !== "none");
}

// ---------------------------------------------------------------- the map
function drawWorld(world) {
  studio.drawnParts = {};
  const svg = $("map");
  svg.innerHTML = "";
  const grid = world.grid;
  studio.grid = grid;
  svg.setAttribute("viewBox", `0 0 ${grid.width} ${grid.height}`);
  const bg = el("rect", { x: 0, y: 0, width: grid.width, height: grid.height, fill: "#fafaf7" });
  svg.appendChild(bg);
  const d = grid.walls.map(([row, col, n]) =>
    `M${col} ${grid.height - 1 - row}h${n}v1h${-n}z`).join("");
  svg.appendChild(el("path", { d, fill: "#373c44", id: "walls" }));
  const res = grid.resolution;
  svg.appendChild(el("polyline", { id: "path", fill: "none", stroke: "#1e6edc",
                                   "stroke-width": 0.06 / res * 1.5, points: "" }));
  const places = el("g", { id: "places" });
  world.places.forEach((z, i) => {
    const [cx, cy] = toMap(z.x, z.y);
    const g = el("g", { "data-place": z.id });
    g.appendChild(el("circle", { cx, cy, r: 0.3 / res, fill: "none", stroke: "#888",
                                 "stroke-width": 0.05 / res }));
    const label = el("text", { x: cx, y: cy + 0.12 / res, "font-size": 0.35 / res,
                               "text-anchor": "middle", fill: "#555" });
    label.textContent = String(i + 1);
    g.appendChild(label);
    places.appendChild(g);
  });
  svg.appendChild(places);
  if (world.base) {
    const [bx, by] = toMap(world.base.x, world.base.y);
    const s = 0.4 / res;
    svg.appendChild(el("rect", { x: bx - s / 2, y: by - s / 2, width: s, height: s,
                                 fill: "none", stroke: "#7846c8", "stroke-width": 0.06 / res }));
  }
  svg.appendChild(el("g", { id: "found" }));
  const r = 0.22 / res;
  const robot = el("polygon", { id: "robot", points: `${r},0 ${-r * 0.7},${r * 0.7} ${-r * 0.7},${-r * 0.7}`,
                                fill: "#1e6edc", stroke: "#fff", "stroke-width": 0.03 / res,
                                visibility: "hidden" });
  svg.appendChild(robot);
  if (studio.frame) paintWorld(studio.frame);
}

function toMap(x, y) {
  const g = studio.grid;
  return [(x - g.origin[0]) / g.resolution, g.height - (y - g.origin[1]) / g.resolution];
}

function el(name, attrs) {
  const e = document.createElementNS(SVGNS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  return e;
}

// ---------------------------------------------------------------- frames
function onFrame(frame) {
  studio.frame = frame;
  studio.framesSeen += 1;
  studio.t = frame.t;
  $("tick").textContent = frame.tick;
  $("tps").textContent = frame.tps.toFixed(1);
  const status = $("mission-status");
  status.textContent = frame.complete ? `${frame.status} (over)` : frame.status;
  status.className = `pill ${frame.status}`;
  // The apps' words about the tick (shown only when a tree's app has some).
  $("app-status").hidden = !frame.app_status;
  $("app-status").textContent = frame.app_status;
  paintTree(frame);
  paintWorld(frame);
  fillBlackboard(frame);
  fillReasons(frame);
  if (studio.mode === "replay") showTime(frame.t);
  if (studio.selected) send({ op: "node", uid: studio.selected });
  if (studio.mode === "replay") seekDone();
  else send({ op: "ack" });  // drawn: the server may send the next one
}

function paintTree(frame) {
  for (const [uid, g] of studio.nodes) {
    const entry = frame.nodes[uid];
    const status = entry ? entry[0] : "INVALID";
    if (g.dataset.status === status) continue;
    g.dataset.status = status;
    const fill = studio.colours[status] || studio.colours.INVALID;
    for (const s of shapesOf(g)) s.setAttribute("fill", fill);
    g.classList.toggle("running", status === "RUNNING");
  }
}

function paintWorld(frame) {
  if (!studio.grid) return;
  $("path").setAttribute("points", frame.path.map(([x, y]) => toMap(x, y).join(",")).join(" "));
  const robot = $("robot");
  if (frame.robot) {
    const [x, y, yaw] = frame.robot;
    const [cx, cy] = toMap(x, y);
    robot.setAttribute("transform", `translate(${cx} ${cy}) rotate(${-yaw * 180 / Math.PI})`);
    robot.setAttribute("visibility", "visible");
    robot.dataset.x = x.toFixed(3);
    robot.dataset.y = y.toFixed(3);
  }
  if (!changedSince("world", [frame.found, frame.reached])) return;
  const found = $("found");
  found.innerHTML = "";
  const res = studio.grid.resolution;
  for (const s of frame.found) {
    const [cx, cy] = toMap(s.position[0], s.position[1]);
    const dot = el("circle", { cx, cy, r: 0.15 / res, fill: "#e67e00", "data-id": s.id });
    const tip = el("title", {});
    tip.textContent = s.id || "detected";
    dot.appendChild(tip);
    found.appendChild(dot);
  }
  for (const g of $("places").children) {
    const reached = frame.reached.includes(g.dataset.place);
    g.firstChild.setAttribute("stroke", reached ? "#2e8b3e" : "#888");
    g.firstChild.setAttribute("fill", reached ? "rgba(46,139,62,0.2)" : "none");
  }
}

function changedSince(key, value) {  // whether a part of the frame differs from the last drawn
  const text = JSON.stringify(value);
  if (studio.drawnParts[key] === text) return false;
  studio.drawnParts[key] = text;
  return true;
}

function fillBlackboard(frame) {
  if (!changedSince("blackboard", [frame.entries, frame.blackboard])) return;
  const rows = [];
  for (const [name, e] of Object.entries(frame.entries)) rows.push([name, e.value, `${e.type || ""} ← ${e.writer || ""}`]);
  for (const [key, value] of Object.entries(frame.blackboard)) rows.push([key, value, ""]);
  const body = $("blackboard").tBodies[0];
  body.innerHTML = "";
  if (!rows.length) rows.push(["(no entries)", "", ""]);
  for (const [name, value, note] of rows) {
    const tr = body.insertRow();
    tr.insertCell().textContent = name;
    tr.insertCell().textContent = value;
    tr.title = note;
  }
}

function fillReasons(frame) {
  if (!changedSince("reasons", frame.reasons)) return;
  const list = $("reasons");
  list.innerHTML = "";
  for (const r of frame.reasons) {
    const li = document.createElement("li");
    li.className = r.kind;
    li.innerHTML = `<span class="kind"></span> <span class="node"></span>: <span class="msg"></span> <small></small>`;
    li.querySelector(".kind").textContent = r.kind;
    li.querySelector(".node").textContent = r.node || "mission";
    li.querySelector(".msg").textContent = r.message;
    li.querySelector("small").textContent = `@ ${(r.t - startOf()).toFixed(1)} s`;
    li.addEventListener("click", () => { if (r.uid) selectNode(r.uid); if (studio.mode === "replay") seek(r.t); });
    list.appendChild(li);
  }
}

// ---------------------------------------------------------------- the node panel
function selectNode(uid) {
  if (studio.selected && studio.nodes.get(studio.selected)) studio.nodes.get(studio.selected).classList.remove("selected");
  studio.selected = uid;
  if (studio.nodes.get(uid)) studio.nodes.get(uid).classList.add("selected");
  send({ op: "node", uid });
}

function showNode(msg) {
  if (msg.uid !== studio.selected) return;
  const facts = msg.facts || { uid: msg.uid, name: msg.uid, kind: "?" };
  $("node-panel").hidden = false;
  $("node-title").textContent = `${facts.name} [${facts.kind}] ${facts.uid}`;
  const body = $("node-body");
  body.innerHTML = "";
  const table = document.createElement("table");
  const add = (k, v) => { const tr = table.insertRow(); tr.insertCell().textContent = k; tr.insertCell().textContent = v; };
  if (facts.location) add("at", facts.location);
  for (const [k, v] of Object.entries(facts.params || {})) add(`param ${k}`, JSON.stringify(v));
  for (const [k, v] of Object.entries(facts.ports || {})) add(`port ${k}`, JSON.stringify(v));
  for (const [k, v] of Object.entries(facts.refs || {})) add(`ref ${k}`, v);
  const now = studio.frame && studio.frame.nodes[msg.uid];
  if (now && now[1]) add("message", now[1]);
  add("last reason", msg.last_reason ? `${msg.last_reason.kind}: ${msg.last_reason.message}` : "-");
  body.appendChild(table);
  const history = document.createElement("div");
  history.className = "history";
  history.textContent = "history: ";
  for (const [t, status] of msg.history) {
    const span = document.createElement("span");
    span.style.background = studio.colours[status] || "#ddd";
    span.textContent = `${(t - startOf()).toFixed(1)} ${status}`;
    history.appendChild(span);
  }
  body.appendChild(history);
}

// ---------------------------------------------------------------- the replay timeline
function startOf() { return studio.hello && studio.mode === "replay" ? studio.hello.timeline.start : 0; }

function setupTimeline(timeline) {
  $("timeline").hidden = false;
  const scrubber = $("scrubber");
  scrubber.min = timeline.start;
  scrubber.max = timeline.end;
  const span = Math.max(timeline.end - timeline.start, 1e-6);
  const marks = $("marks");
  marks.innerHTML = "";
  for (const m of timeline.marks) {
    const mark = document.createElement("div");
    mark.className = `mark ${m.kind}`;
    mark.style.left = `${(100 * (m.t - timeline.start)) / span}%`;
    mark.title = `${m.label} @ ${(m.t - timeline.start).toFixed(1)} s`;
    mark.dataset.t = m.t;
    mark.dataset.kind = m.kind;
    mark.addEventListener("click", () => { pause(); seek(m.t); });
    marks.appendChild(mark);
  }
  fillEvents(timeline.events || [], timeline.start);  // events.js
  scrubber.oninput = () => { pause(); seek(parseFloat(scrubber.value)); };
  $("play").onclick = () => (studio.playing ? pause() : play());
  $("speed").onchange = () => { studio.speed = parseFloat($("speed").value); };
}

function showTime(t) {
  $("scrubber").value = t;
  $("clock").textContent = `${(t - startOf()).toFixed(1)} s`;
  showEventAt(t);  // events.js
}

function seek(t) {  // at most one seek in flight; the newest wanted one goes next
  if (studio.seekPending) { studio.seekWanted = t; return; }
  studio.seekPending = true;
  send({ op: "seek", t });
}

function seekDone() {
  studio.seekPending = false;
  if (studio.seekWanted !== null) { const t = studio.seekWanted; studio.seekWanted = null; seek(t); }
}

function play() {
  studio.playing = true;
  $("play").textContent = "❚❚";
  if (studio.t >= studio.hello.timeline.end) studio.t = studio.hello.timeline.start;
  studio.lastStep = performance.now();
  requestAnimationFrame(step);
}

function pause() { studio.playing = false; $("play").textContent = "▶"; }

function step(now) {
  if (!studio.playing) return;
  const end = studio.hello.timeline.end;
  const t = Math.min(end, studio.t + ((now - studio.lastStep) / 1000) * studio.speed);
  studio.lastStep = now;
  studio.t = t;
  showTime(t);
  if (!studio.seekPending) seek(t);
  if (t >= end) { pause(); return; }
  requestAnimationFrame(step);
}

$("node-close").onclick = () => {
  $("node-panel").hidden = true;
  const g = studio.selected && studio.nodes.get(studio.selected);
  if (g) g.classList.remove("selected");
  studio.selected = null;
};
connect();
