// sar-tree studio: the tree editor. A textarea over a highlighted copy of its text; each
// change is checked by the server (the diagnostics of `sar-tree validate`) and, in edit mode,
// a valid one redraws the diagram; completion offers the kinds and params of the JSON Schema;
// Save writes the file with the session token. Live, it edits the running mission's tree
// file (opened by "Edit tree"), and "Apply to mission" saves it and has the runner swap it in
// (hot reload); the diagram stays the running tree's until the swap redraws it.
"use strict";

const editor = { path: null, kinds: {}, top: [], timer: null, checked: null, options: [],
                 chosen: 0, badLines: new Set(), live: false, applied: null };
window.editor = editor;  // the browser tests read it

window.startEditor = (edit, mode) => {
  editor.path = edit.path;
  editor.kinds = edit.completions.kinds;
  editor.top = edit.completions.top;
  editor.live = mode === "live";
  $("apply").hidden = !editor.live;
  if (editor.live) {
    $("edit-open").hidden = false;
    $("edit-open").onclick = () => { $("editor-pane").hidden = !$("editor-pane").hidden; };
  } else {
    $("editor-pane").hidden = false;
    document.querySelector("aside").hidden = true;
    $("run-info").hidden = true;
  }
  $("edit-path").textContent = edit.path;
  $("edit-path").title = edit.path;
  const source = $("source");
  if (source.dataset.loaded !== "yes") {
    source.value = edit.text;
    source.dataset.loaded = "yes";
    source.addEventListener("input", changed);
    source.addEventListener("scroll", syncScroll);
    source.addEventListener("keydown", onKey);
    $("save").addEventListener("click", save);
    $("apply").addEventListener("click", apply);
  }
  paint();
  check();
};

function changed() {
  paint();
  complete();
  clearTimeout(editor.timer);
  editor.timer = setTimeout(check, 150);
}

function check() { send({ op: "check", text: $("source").value }); }

window.onChecked = (msg) => {
  editor.checked = msg;
  editor.badLines = new Set(msg.diagnostics.filter((d) => d.severity === "error" && d.file === editor.path)
    .map((d) => d.line));
  const list = $("diagnostics");
  list.innerHTML = "";
  for (const d of msg.diagnostics) {
    const li = document.createElement("li");
    li.className = d.severity;
    li.textContent = d.text;
    li.addEventListener("click", () => goTo(d.line, d.col));
    list.appendChild(li);
  }
  if (msg.ok) {
    const li = document.createElement("li");
    li.className = "ok";
    li.textContent = "✓ valid";
    list.appendChild(li);
    if (msg.tree && !editor.live) drawTree(msg.tree);
  }
  paint();
};

function goTo(line, col) {
  const source = $("source");
  const lines = source.value.split("\n");
  let at = 0;
  for (let i = 0; i < line - 1 && i < lines.length; i += 1) at += lines[i].length + 1;
  source.focus();
  source.setSelectionRange(at + col - 1, at + col - 1);
}

// ---------------------------------------------------------------- highlighting
function escapeHtml(text) {
  return text.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
}

const TOKENS = /^(\s*(?:- )?)([A-Za-z_][\w.?-]*)(?=:)|("\{[^"]*\}"|'\{[^']*\}')|("[^"]*"|'[^']*')|(#.*$)|(\b-?\d+(?:\.\d+)?\b|\btrue\b|\bfalse\b|\bnull\b)/g;

function highlightLine(line) {  // keys, {references}, strings, comments, scalars
  let html = "";
  let at = 0;
  for (const m of line.matchAll(TOKENS)) {
    html += escapeHtml(line.slice(at, m.index));
    if (m[2] !== undefined) html += `${escapeHtml(m[1])}<span class="k">${escapeHtml(m[2])}</span>`;
    else if (m[3] !== undefined) html += `<span class="r">${escapeHtml(m[3])}</span>`;
    else if (m[4] !== undefined) html += `<span class="s">${escapeHtml(m[4])}</span>`;
    else if (m[5] !== undefined) html += `<span class="c">${escapeHtml(m[5])}</span>`;
    else html += `<span class="n">${escapeHtml(m[6])}</span>`;
    at = m.index + m[0].length;
  }
  return html + escapeHtml(line.slice(at));
}

function paint() {
  const lines = $("source").value.split("\n");
  $("highlight").innerHTML = lines.map((line, i) => {
    const html = highlightLine(line) || " ";
    return editor.badLines.has(i + 1) ? `<span class="bad">${html}</span>` : html;
  }).join("\n") + "\n";
  syncScroll();
}

function syncScroll() {
  $("highlight").scrollTop = $("source").scrollTop;
  $("highlight").scrollLeft = $("source").scrollLeft;
}

// ---------------------------------------------------------------- completion
function wordBefore() {
  const source = $("source");
  const before = source.value.slice(0, source.selectionStart);
  const match = before.match(/[A-Za-z_][\w]*$/);
  return match ? match[0] : "";
}

function candidates(word) {
  const found = new Map();
  for (const [kind, facts] of Object.entries(editor.kinds)) {
    if (kind.startsWith(word)) found.set(kind, facts.description);
    for (const [param, about] of Object.entries(facts.params)) {
      if (param.startsWith(word) && !found.has(param)) found.set(param, about);
    }
  }
  for (const key of editor.top) if (key.startsWith(word) && !found.has(key)) found.set(key, "");
  found.delete(word);
  return [...found.entries()].sort((a, b) => a[0].length - b[0].length || a[0].localeCompare(b[0])).slice(0, 12);
}

function complete() {
  const word = wordBefore();
  const list = $("completions");
  editor.options = word.length >= 2 ? candidates(word) : [];
  editor.chosen = 0;
  list.hidden = editor.options.length === 0;
  list.innerHTML = "";
  editor.options.forEach(([name, about], i) => {
    const li = document.createElement("li");
    li.className = i === 0 ? "on" : "";
    li.textContent = name;
    const small = document.createElement("small");
    small.textContent = about.slice(0, 70);
    li.appendChild(small);
    li.addEventListener("mousedown", (e) => { e.preventDefault(); accept(i); });
    list.appendChild(li);
  });
}

function accept(i) {
  const source = $("source");
  const word = wordBefore();
  const [name] = editor.options[i];
  const at = source.selectionStart;
  source.setRangeText(name.slice(word.length), at, at, "end");
  $("completions").hidden = true;
  editor.options = [];
  changed();
  $("completions").hidden = true;
}

function onKey(e) {
  const open = !$("completions").hidden && editor.options.length;
  if (open && (e.key === "Tab" || e.key === "Enter")) { e.preventDefault(); accept(editor.chosen); return; }
  if (open && (e.key === "ArrowDown" || e.key === "ArrowUp")) {
    e.preventDefault();
    const n = editor.options.length;
    editor.chosen = (editor.chosen + (e.key === "ArrowDown" ? 1 : n - 1)) % n;
    [...$("completions").children].forEach((li, i) => li.classList.toggle("on", i === editor.chosen));
    return;
  }
  if (e.key === "Escape") { $("completions").hidden = true; return; }
  if (e.key === "Tab") { e.preventDefault(); $("source").setRangeText("  ", $("source").selectionStart, $("source").selectionEnd, "end"); changed(); }
}

// ---------------------------------------------------------------- saving, applying
async function post(url, body) {
  const answer = await fetch(url, {
    method: "POST", headers: { "content-type": "application/json", "x-studio-token": studio.token || "" },
    body: JSON.stringify(body),
  });
  return [answer.ok, await answer.json()];
}

// Hot reload: the server saves the text to the mission's tree file and asks its runner to
// swap it in; the runner's answer (the swap's summary, or why it refused) is shown here.
async function apply() {
  const state = $("save-state");
  state.textContent = "applying…";
  try {
    const [ok, body] = await post("/api/reload", { text: $("source").value });
    editor.applied = body;
    if (ok) {
      state.textContent = `${body.swapped ? "applied" : "refused by the mission"}: ${body.message}`;
      window.onChecked({ type: "checked", ok: body.ok, diagnostics: body.diagnostics, tree: null });
    } else {
      state.textContent = `not applied: ${body.error}`;
    }
  } catch (err) {
    state.textContent = `not applied: ${err}`;
  }
}

async function save() {
  const state = $("save-state");
  state.textContent = "saving…";
  try {
    const [ok, body] = await post("/api/save", { text: $("source").value });
    state.textContent = ok ? `saved ${body.saved}${body.ok ? "" : " (with errors)"}`
      : `not saved: ${body.error}`;
    if (ok) window.onChecked({ ...body, type: "checked" });
  } catch (err) {
    state.textContent = `not saved: ${err}`;
  }
}
